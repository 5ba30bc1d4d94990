// Pipeline: render. See renderer.h.
#include "render/renderer.h"

namespace lray {

Film renderFrame(const Scene &scene, const Accelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts, const ProgressFn &progress) {
  Film film(settings.width, settings.height);
  accel.render(scene, images, settings, film, counts, progress);
  return film;
}

} // namespace lray
