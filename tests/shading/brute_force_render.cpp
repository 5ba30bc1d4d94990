// The integrator and the tile loop instantiated for the tests' brute-force
// accelerator, as render/backends.cpp does for the real backends.
#include "shading/brute_force_accelerator.h"
#include "shading/counting_accelerator.h"

#include "render/tile_renderer_impl.h"
#include "shading/path_integrator_impl.h"

namespace lray {

// integrator_test.cpp and path_integrator_test.cpp call the integrators directly too.
template class Integrator<testing::BruteForceAccelerator>;
template class Integrator<testing::CountingAccelerator>;
template class PathIntegrator<testing::BruteForceAccelerator>;

namespace testing {

Film renderFrame(const Scene &scene, const BruteForceAccelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts, const ProgressFn &progress) {
  Film film(settings.width, settings.height);
  if (settings.integrator == IntegratorKind::Path)
    renderTiles<PathIntegrator<BruteForceAccelerator>>(accel, scene, images, settings, film,
                                                       counts, progress);
  else
    renderTiles<Integrator<BruteForceAccelerator>>(accel, scene, images, settings, film, counts,
                                                   progress);
  return film;
}

} // namespace testing
} // namespace lray
