// Pipeline: application. One frame, end to end.
#include "run/frame_pipeline.h"

#include "bindings/scene_script.h"
#include "render/backends.h"
#include "run/render_threads.h"
#include "run/scene_motion.h"
#include "scene/scene_checks.h"
#include "shading/image_cache.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <chrono>
#include <memory>
#include <tuple>

namespace lray {

Scene buildFrameScene(SceneScript &script, const SceneInfo &info, int frame, int &calls) {
  const std::vector<double> clocks = motionClocks(info, frame);
  calls = static_cast<int>(clocks.size());
  if (clocks.size() == 1) return script.buildFrame(clocks[0]);
  std::vector<Scene> steps;
  steps.reserve(clocks.size());
  for (double clock : clocks)
    steps.push_back(script.buildFrame(clock));
  return foldMotionSteps(std::move(steps), clocks);
}

Film renderScriptFrame(SceneScript &script, const SceneInfo &info, int frame,
                       std::string_view backend, ImageCache &images, FrameStats &stats,
                       const ProgressFn &progress, const FrameSettings &sampling) {
  stats.frame = frame;
  stats.clock = info.clockForFrame(frame);

  auto t0 = std::chrono::steady_clock::now();
  Scene scene = buildFrameScene(script, info, frame, stats.sceneCalls);
  stats.sceneSeconds = secondsSince(t0);
  stats.entities = scene.entities.size();
  stats.lights = scene.lights.size();
  if (auto warning = aspectWarning(info, scene.camera)) stats.warnings.push_back(*warning);
  // The edge lattice's points and the sparse centres' fills have no lens
  // or time samples (render/tile_renderer_impl.h): such a camera takes the
  // Sobol passes, and every centre.
  const bool lens = scene.camera.kind == CameraKind::Perspective && scene.camera.aperture > 0;
  if (lens || scene.motionSteps >= 2) {
    const AdaptiveSettings &a = sampling.adaptiveSettings;
    for (const auto &[on, flag, instead] :
         {std::tuple{a.latticeDepth > 0, "--edge-lattice", "Sobol passes instead"},
          std::tuple{a.sparseCentres, "--sparse-centres", "every centre traced instead"}})
      if (on)
        stats.warnings.push_back(fmt::format("{}: the camera's {} needs samples of its own; {}",
                                             flag, lens ? "lens" : "open shutter", instead));
  }

  t0 = std::chrono::steady_clock::now();
  images.load(scene);
  stats.imageSeconds = secondsSince(t0);

  // The render threads, asleep since the last frame (or since start-up),
  // woken now: they are up by the time the build ends. Embree's build,
  // parallel, woke them anyway; a small scene's kd-tree build is serial,
  // and the second thread then joined the frame's first tiles 1-4 ms late
  // in about half the runs (bench/README.md, "Throughput"). Not with one
  // thread: TBB starts a worker for an enqueued task even then, and it
  // would render beside the main thread.
  if (tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1)
    wakeRenderThreads();
  std::unique_ptr<Accelerator> accel = makeAccelerator(backend, scene);
  stats.accel = accel->stats();

  FrameSettings settings = sampling;
  settings.width = info.imageWidth;
  settings.height = info.imageHeight;
  settings.samples = info.samples;
  settings.frameIndex = frame;
  t0 = std::chrono::steady_clock::now();
  Film film = renderFrame(scene, *accel, images, settings, stats.rays, progress);
  stats.renderSeconds = secondsSince(t0);
  stats.sampling = film.report;
  return film;
}

} // namespace lray
