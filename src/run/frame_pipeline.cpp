// Pipeline: application. One frame, end to end.
#include "run/frame_pipeline.h"

#include "bindings/scene_script.h"
#include "scene/scene_checks.h"
#include "shading/image_cache.h"
#include "render/backends.h"

#include <chrono>
#include <memory>

namespace lray {

Film renderScriptFrame(SceneScript &script, const SceneInfo &info, int frame,
                       std::string_view backend, ImageCache &images, FrameStats &stats,
                       const ProgressFn &progress, const FrameSettings &sampling) {
  stats.frame = frame;
  stats.clock = info.clockForFrame(frame);

  auto t0 = std::chrono::steady_clock::now();
  Scene scene = script.buildFrame(stats.clock);
  stats.sceneSeconds = secondsSince(t0);
  stats.entities = scene.entities.size();
  stats.lights = scene.lights.size();
  if (auto warning = aspectWarning(info, scene.camera)) stats.warnings.push_back(*warning);

  t0 = std::chrono::steady_clock::now();
  images.load(scene);
  stats.imageSeconds = secondsSince(t0);

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
