// Pipeline: run. The sampling group of options (sampling_options.cpp) and
// the settings it fills: the frame's size and samples over scene_info, and
// how pixels are sampled.
#pragma once

#include "render/frame_settings.h"
#include "run/options.h"
#include "scene/scene.h"

namespace lray {

/// Applies the command-line overrides to scene_info and checks the result
/// (positive sizes, the --max-pixels cap, the frame range). Throws SceneError.
SceneInfo effectiveSceneInfo(const SceneInfo &fromScript, const Options &options);

/// How pixels are sampled, from the options and scene_info: adaptive when a
/// noise threshold or a time limit is given, with its sample bounds and
/// light sampling. Throws SceneError on a contradiction (e.g. --max-samples
/// without adaptive sampling) or work above --max-pixels.
FrameSettings samplingSettings(const SceneInfo &info, const Options &options);

} // namespace lray
