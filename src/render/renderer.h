// Pipeline: render. Renders one frame of a converted scene with a built
// backend: TBB schedules 16x16 pixel tiles; every pixel's samples use a
// counter-based random stream keyed by (frame, pixel, sample), so the image
// is the same whatever the thread count or the order tiles run in.
#pragma once

#include "accel/accelerator.h"
#include "render/film.h"
#include "scene/scene.h"
#include "shading/ray_counts.h"

#include <functional>

namespace lray {

class ImageCache;

/// What one frame is rendered at.
struct FrameSettings {
  int width = 800;
  int height = 600;
  int samples = 1;    ///< n: n x n stratified jittered samples per pixel
  int frameIndex = 0; ///< part of the random-stream key
};

/// Called after each finished tile with (tiles done, tiles total), from
/// worker threads: must be thread-safe.
using ProgressFn = std::function<void(size_t, size_t)>;

constexpr int kTileSize = 16;

/// Renders `scene` into a new film. Returns the rays traced, by kind.
/// Non-finite sample values are replaced by black and counted.
Film renderFrame(const Scene &scene, const Accelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts,
                 const ProgressFn &progress = nullptr);

} // namespace lray
