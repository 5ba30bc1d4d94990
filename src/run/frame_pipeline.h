// Pipeline: run. One frame through the whole pipeline: scene(clock)
// -> scene model -> backend -> shading -> film. Shared by the CLI and the
// reference-image checker so both render exactly the same way.
#pragma once

#include "render/backends.h"
#include "run/render_stats.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace lray {

class SceneScript;
class ImageCache;

/// Frame `frame`'s scene: scene(clock) at the frame's clock, or, with motion
/// blur (info.shutter > 0), at each of its motion steps folded into one
/// (scene/scene_motion.h). `calls`: how many times scene(clock) ran.
Scene buildFrameScene(SceneScript &script, const SceneInfo &info, int frame, int &calls);

/// Renders 0-based frame `frame` of `script` at the size and sampling of
/// `info` with the backend named `backend` (render/backends.h backends()),
/// filling `stats` (times, rays, backend figures, sampling). `sampling`
/// gives the adaptive, light-sampling and cancel fields (RunPlan's
/// frameSettings, run/run_plan.h); the size, samples and frame come from
/// `info` and `frame`.
Film renderScriptFrame(SceneScript &script, const SceneInfo &info, int frame,
                       std::string_view backend, ImageCache &images, FrameStats &stats,
                       const ProgressFn &progress = nullptr, const FrameSettings &sampling = {});

} // namespace lray
