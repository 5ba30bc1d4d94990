// Pipeline: application (live preview). `lray --watch`: renders a scene
// progressively (a quick first look at one sample per pixel, then the
// adaptive sampler's passes), publishes every pass to the preview page
// (--serve) and to <outdir>, and starts again whenever the scene file or a
// file it read changes, or the page asks for another frame or backend. A
// script error is shown and the last good image stays. Ends on Ctrl-C.
#pragma once

#include "run/options.h"

namespace lray {

/// The sampling --watch renders with: `noise_threshold` (option, else
/// scene_info, else 0.01), `--min-samples` (else 4) and `--max-samples`
/// (else 256), adaptive; a render with these gives the final image.
FrameSettings watchSampling(const SceneInfo &info, const Options &options);

int runWatch(const Options &options);

} // namespace lray
