// Pipeline: render. The tile loop of one frame, for one concrete backend:
// TBB schedules 16x16 pixel tiles; every pixel's samples use a
// counter-based random stream keyed by (frame, pixel, sample), so the image
// is the same whatever the thread count or the order tiles run in. The
// definition is in tile_renderer_impl.h, instantiated once per backend and
// integrator in render/backends.cpp.
#pragma once

#include "render/film.h"
#include "render/frame_settings.h"
#include "scene/scene.h"
#include "shading/ray_counts.h"

namespace lray {

class ImageCache;

/// Renders `scene` with `accel` and the integrator `Integ` (a class
/// template of shading/ instantiated for Accel) into `film`
/// (settings.width x height), adding the rays traced to `counts`.
/// Non-finite sample values are replaced by black and counted.
template <class Integ, class Accel>
void renderTiles(const Accel &accel, const Scene &scene, const ImageCache &images,
                 const FrameSettings &settings, Film &film, RayCounts &counts,
                 const ProgressFn &progress);

} // namespace lray
