// Pipeline: acceleration -> shading -> render. The integrator and the tile
// loop instantiated for KdTreeAccelerator: its queries are direct calls below
// Accelerator::render.
#include "accel/kdtree/kdtree_accelerator.h"

#include "render/tile_renderer_impl.h"

namespace lray {

template class Integrator<KdTreeAccelerator>;

void KdTreeAccelerator::render(const Scene &scene, const ImageCache &images,
                                const FrameSettings &settings, Film &film, RayCounts &counts,
                                const ProgressFn &progress) const {
  renderTiles(*this, scene, images, settings, film, counts, progress);
}

} // namespace lray
