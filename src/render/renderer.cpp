// Pipeline: render. See renderer.h.
#include "render/renderer.h"

#include "render/backends.h"

namespace lray {

Film renderFrame(const Scene &scene, const Accelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts, const ProgressFn &progress) {
  Film film(settings.width, settings.height);
  const RenderFn render = backendOf(accel).render[static_cast<size_t>(settings.integrator)];
  render(accel, scene, images, settings, film, counts, progress);
  return film;
}

} // namespace lray
