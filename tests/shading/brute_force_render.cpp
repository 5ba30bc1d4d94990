// The integrator and the tile loop instantiated for the tests' brute-force
// accelerator, as src/accel/*/..._render.cpp do for the real backends.
#include "shading/brute_force_accelerator.h"

#include "render/tile_renderer_impl.h"

namespace lray {

template class Integrator<testing::BruteForceAccelerator>;

namespace testing {

void BruteForceAccelerator::render(const Scene &scene, const ImageCache &images,
                                   const FrameSettings &settings, Film &film, RayCounts &counts,
                                   const ProgressFn &progress) const {
  renderTiles(*this, scene, images, settings, film, counts, progress);
}

} // namespace testing
} // namespace lray
