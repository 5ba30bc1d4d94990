// Pipeline: run. The limits group of options (limit_options.cpp) and the
// script settings it fills.
#pragma once

#include "bindings/scene_script.h"
#include "run/options.h"

namespace lray {

/// The script limits and sandbox the options ask for.
ScriptOptions scriptOptionsOf(const Options &options);

} // namespace lray
