// Pipeline: render. The definition of tile_renderer.h; included only where
// it is instantiated for a concrete backend.
#pragma once

#include "math/random.h"
#include "render/camera_rays.h"
#include "render/tile_renderer.h"
#include "shading/integrator_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <xmmintrin.h>

namespace lray {

namespace tile_detail {

// Denormals are flushed to zero on render threads: they cost 100x on x86 and
// never change a visible value.
inline void setFlushToZero() { _mm_setcsr(_mm_getcsr() | 0x8040); }

} // namespace tile_detail

template <class Accel>
void renderTiles(const Accel &accel, const Scene &scene, const ImageCache &images,
                 const FrameSettings &settings, Film &film, RayCounts &counts,
                 const ProgressFn &progress) {
  const Integrator<Accel> integrator(scene, accel, images);
  const CameraRays camera(scene.camera, settings.width, settings.height);
  const int n = settings.samples;
  const double invSamples = 1.0 / (static_cast<double>(n) * n);
  const int tilesX = (settings.width + kTileSize - 1) / kTileSize;
  const int tilesY = (settings.height + kTileSize - 1) / kTileSize;
  const size_t tileCount = static_cast<size_t>(tilesX) * tilesY;
  std::atomic<size_t> tilesDone{0};
  tbb::combinable<RayCounts> perThread;

  using Tiles = tbb::blocked_range<size_t>;
  tbb::parallel_for(Tiles(0, tileCount, 1), [&](const Tiles &r) {
    tile_detail::setFlushToZero();
    constexpr int kTilePixels = kTileSize * kTileSize;
    std::array<Ray, kTilePixels> rays;
    std::array<Hit, kTilePixels> hits;
    std::array<uint8_t, kTilePixels> found;
    std::array<Sampler, kTilePixels> samplers;
    std::array<Color, kTilePixels> sums, colors;
    static_assert(kTilePixels <= Integrator<Accel>::kMaxTileRays);
    RayCounts &local = perThread.local();
    for (size_t tile = r.begin(); tile != r.end(); ++tile) {
      const int x0 = static_cast<int>(tile % tilesX) * kTileSize;
      const int y0 = static_cast<int>(tile / tilesX) * kTileSize;
      const int x1 = std::min(x0 + kTileSize, settings.width);
      const int y1 = std::min(y0 + kTileSize, settings.height);
      const int tileWidth = x1 - x0;
      const size_t count = static_cast<size_t>(tileWidth) * (y1 - y0);
      sums.fill(Color());
      for (int s = 0; s < n * n; ++s) {
        const int sx = s % n, sy = s / n;
        for (size_t i = 0; i < count; ++i) {
          const int x = x0 + static_cast<int>(i) % tileWidth;
          const int y = y0 + static_cast<int>(i) / tileWidth;
          const uint64_t pixel = static_cast<uint64_t>(y) * settings.width + x;
          samplers[i] = Sampler(static_cast<uint64_t>(settings.frameIndex), pixel,
                                static_cast<uint64_t>(s));
          const double jx = samplers[i].next(), jy = samplers[i].next();
          rays[i] = camera.generate(x + (sx + jx) / n, y + (sy + jy) / n);
        }
        accel.intersectCoherent(rays.data(), count, hits.data(), found.data());
        local.camera += count;
        integrator.shadeTile(rays.data(), hits.data(), found.data(), samplers.data(), count,
                             colors.data(), local);
        for (size_t i = 0; i < count; ++i) {
          Color c = colors[i];
          if (!isFinite(c)) {
            ++local.nonFinite;
            c = Color();
          }
          sums[i] += c;
        }
      }
      for (size_t i = 0; i < count; ++i)
        film.set(x0 + static_cast<int>(i) % tileWidth, y0 + static_cast<int>(i) / tileWidth,
                 sums[i] * invSamples);
      size_t done = ++tilesDone;
      if (progress) progress(done, tileCount);
    }
  });
  perThread.combine_each([&](const RayCounts &c) { counts += c; });
}

} // namespace lray
