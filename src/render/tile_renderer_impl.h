// Pipeline: render. The definition of tile_renderer.h; included only where
// it is instantiated for a concrete backend and integrator
// (render/backends.cpp, and the tests' brute-force accelerator).
#pragma once

#include "math/random.h"
#include "render/camera_rays.h"
#include "render/flush_to_zero.h"
#include "render/owen_sobol_lanes.h"
#include "math/owen_sobol.h"
#include "render/pixel_error.h"
#include "render/pixel_lattice.h"
#include "render/sample_buffer.h"
#include "render/sparse_centres.h"
#include "render/tile_renderer.h"
#include "shading/integrator_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <optional>

namespace lray {

namespace tile_detail {

constexpr int kTilePixels = kTileSize * kTileSize;

/// One tile's rectangle in a frame of `tilesX` tiles per row.
struct TileRect {
  int x0, y0, x1, y1;
  TileRect(size_t tile, int tilesX, int width, int height)
      : x0(static_cast<int>(tile % tilesX) * kTileSize),
        y0(static_cast<int>(tile / tilesX) * kTileSize), x1(std::min(x0 + kTileSize, width)),
        y1(std::min(y0 + kTileSize, height)) {}
  int width() const { return x1 - x0; }
  size_t pixels() const { return static_cast<size_t>(x1 - x0) * (y1 - y0); }
  /// Calls f(i, x, y) for each of the tile's pixels i (row by row) with its
  /// image coordinates (x, y).
  template <class F> void forEachPixel(F &&f) const {
    size_t i = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) f(i++, x, y);
  }
};

/// A frame's halves of its pixels' seeds: a pixel's is mix64 of the
/// frame's half and its index, so the tile loop takes one mix64 per pixel
/// and seed, the frame's half made once.
struct FrameSeeds {
  explicit FrameSeeds(uint64_t stream)
      : key(Sampler::frameKey(stream)), pattern(mix64(stream + 0x13198a2e03707344ULL)),
        lens(mix64(stream + 0x452821e638d01377ULL)), time(mix64(stream + 0xbe5466cf34e90c6cULL)),
        stratum(mix64(stream ^ 0x243f6a8885a308d3ULL)) {}
  uint64_t key;     ///< the Sampler's key (Sampler::pixelKeyOf)
  uint64_t pattern; ///< the Owen scramble seed of the progressive sample positions
  uint64_t lens;    ///< the Owen scramble seed of lens samples (a thin-lens camera)
  uint64_t time;    ///< the Owen scramble seed of times in the shutter (motion blur)
  /// The random offset of a pixel's light strata (Integrator, lightShares),
  /// its top 32 bits: the same for all its samples, so consecutive samples
  /// take consecutive shares.
  uint64_t stratum;
};

/// The camera ray of sample s of a pixel through image position (px, py)
/// with its lens point and its time in the shutter: the pixel's sample s
/// in dimensions of their own (scrambled by the pixel's lens and time
/// seeds, FrameSeeds), stratified over the pixel's samples like the
/// positions. The time goes to the sample's `sampler` too (moving
/// lights). A call of its own: the pinhole, unblurred loop stays small.
[[gnu::noinline]] inline Ray lensOrTimedRay(const CameraRays &camera, uint64_t lensPattern,
                                            uint64_t timePattern, uint32_t s, double px,
                                            double py, Sampler &sampler) {
  double lu = 0.5, lv = 0.5;
  if (camera.hasLens()) owenSobol2D(s, lensPattern, lu, lv);
  if (camera.timed()) sampler.time = static_cast<float>(owenSobol1D(s, timePattern));
  return camera.generate(px, py, lu, lv, sampler.time);
}

/// Work arrays of one thread: the camera rays of one sample index over a
/// tile's pixels, and each pixel's sums over the samples it takes. The
/// same for every integrator and backend.
struct TileWork {
  std::array<Ray, kTilePixels> rays;
  /// Image positions of the rays to generate (CameraRays::generateMany).
  std::array<double, kTilePixels> px, py;
  std::array<Hit, kTilePixels> hits;
  std::array<uint8_t, kTilePixels> found;
  std::array<Sampler, kTilePixels> samplers;
  std::array<Color, kTilePixels> colors;
  std::array<uint16_t, kTilePixels> pixelOf; ///< ray j belongs to tile pixel pixelOf[j]
  std::array<uint16_t, kTilePixels> pixelList; ///< the tile pixels with samples to take
  std::array<Color, kTilePixels> sums;
  std::array<Color, kTilePixels> squares; ///< the sum of the samples' squares
  std::array<uint32_t, kTilePixels> first; ///< the tile pixel's first sample index
  std::array<uint32_t, kTilePixels> taken;
  /// Per tile pixel, what its samples' streams share (computed once per
  /// pixel): the Sampler key's pixel part, the Owen scramble seeds of its
  /// positions, lens points and times (the last two when the camera has
  /// them), the offset of its light strata.
  std::array<uint64_t, kTilePixels> samplerKey, pattern, lensPattern, timePattern;
  /// owenScramble(pattern) as rows (OwenRows; not set for a pass of pixel
  /// centres, which needs none), padded so that eight lanes can be read
  /// from any pixel.
  std::array<uint32_t, kTilePixels + kOwenLanes> shuffle{}, sx{}, sy{};
  std::array<uint32_t, kTilePixels> stratumOffset;
  std::array<int, kTilePixels> x, y; ///< the tile pixel's image coordinates
};

/// The calling thread's sparse centres, one for every backend and
/// integrator (as threadTileWork, below).
inline SparseCentres &threadSparseCentres() {
  static thread_local SparseCentres sparse;
  return sparse;
}

/// Traces the camera rays work.rays[0, n) and shades them (their samplers
/// work.samplers) into work.colors, a colour that is not finite counted
/// (counts.nonFinite) and taken as black.
template <class Accel, class Integ>
void traceCameraRays(const Accel &accel, const Integ &integrator, TileWork &work,
                     size_t n, RayCounts &counts) {
  accel.intersectCoherent(work.rays.data(), n, work.hits.data(), work.found.data());
  counts.camera += n;
  integrator.shadeTile(work.rays.data(), work.hits.data(), work.found.data(),
                       work.samplers.data(), n, work.colors.data(), counts);
  for (size_t j = 0; j < n; ++j)
    if (!isFinite(work.colors[j])) {
      ++counts.nonFinite;
      work.colors[j] = Color();
    }
}

/// The pixels to render: settings.crop within the frame, or all of it.
inline PixelWindow window(const FrameSettings &settings) {
  if (settings.crop.empty()) return {0, 0, settings.width, settings.height};
  return {std::clamp(settings.crop.x0, 0, settings.width),
          std::clamp(settings.crop.y0, 0, settings.height),
          std::clamp(settings.crop.x1, 0, settings.width),
          std::clamp(settings.crop.y1, 0, settings.height)};
}

inline bool meets(const TileRect &t, const PixelWindow &w) {
  return t.x0 < w.x1 && w.x0 < t.x1 && t.y0 < w.y1 && w.y0 < t.y1;
}

/// The first pass of Sobol samples: --min-samples, or 4 after the
/// centre-first pass of --min-samples 1.
inline uint32_t firstSobolPass(uint32_t minSamples, uint32_t maxSamples) {
  return minSamples == 1 ? std::min<uint32_t>(4, maxSamples) : minSamples;
}

/// How many passes adaptive sampling takes at most from min to max samples
/// (the schedule of renderTiles).
inline int adaptivePasses(uint32_t minSamples, uint32_t maxSamples) {
  const uint32_t first = firstSobolPass(minSamples, maxSamples);
  int passes = minSamples == 1 ? 2 : 1;
  if (minSamples == 1 && maxSamples == 1) return 1;
  for (uint32_t target = first; target < maxSamples; ++passes)
    target = std::min(maxSamples, target + std::max(first, target / 4 * 2));
  return passes;
}

} // namespace tile_detail

/// sampleTile's pass of pixel centres (sample 0 of each tile pixel i with
/// work.first[i] == 0): the same rays, samplers and sums, in one loop over
/// the pixels; the Sobol passes' machinery (sample indices, position
/// lanes, batches across indices) is not needed for one ray a pixel, and
/// cost frames of one ray a pixel a fifth of their instructions.
template <class Accel, class Integ>
void sampleCentres(const Accel &accel, const Integ &integrator, const CameraRays &camera,
                   const FrameSettings &settings, const tile_detail::TileRect &rect,
                   bool spreadLight, tile_detail::TileWork &work, RayCounts &counts) {
  const tile_detail::FrameSeeds seeds(settings.stream());
  const bool path = settings.integrator == IntegratorKind::Path;
  const bool pinhole = !camera.hasLens() && !camera.timed();
  const uint64_t width = static_cast<uint64_t>(settings.width);
  size_t rays = 0;
  rect.forEachPixel([&](size_t i, int x, int y) {
    work.taken[i] = 0;
    if (work.first[i] != 0) {
      work.sums[i] = Color();
      work.squares[i] = Color();
      return;
    }
    const uint64_t pixel = static_cast<uint64_t>(y) * width + x;
    Sampler &sampler = work.samplers[rays];
    sampler = Sampler(Sampler::pixelKeyOf(seeds.key, pixel), 0);
    if (path) sampler.stratify(0, mix64(seeds.pattern ^ pixel));
    if (spreadLight) sampler.lightStratum = static_cast<uint32_t>(mix64(seeds.stratum ^ pixel) >> 32);
    const double px = x + 0.5, py = y + 0.5;
    if (pinhole) [[likely]] {
      work.px[rays] = px;
      work.py[rays] = py;
    } else {
      work.rays[rays] = tile_detail::lensOrTimedRay(camera, mix64(seeds.lens ^ pixel),
                                                    mix64(seeds.time ^ pixel), 0, px, py, sampler);
    }
    work.pixelOf[rays++] = static_cast<uint16_t>(i);
  });
  if (rays == 0) return;
  if (pinhole) camera.generateMany(work.px.data(), work.py.data(), rays, work.rays.data());
  tile_detail::traceCameraRays(accel, integrator, work, rays, counts);
  for (size_t j = 0; j < rays; ++j) {
    // Color() + c, not c: the sum of one sample, as sampleTile's (-0 becomes +0).
    const Color &c = work.colors[j];
    const size_t i = work.pixelOf[j];
    work.sums[i] = Color() + c;
    work.squares[i] = Color() + c * c;
    work.taken[i] = 1;
  }
}

/// Takes samples [work.first[i], end) of each tile pixel i with first[i] <
/// end, summing their colours into work.sums (and their squares into
/// work.squares). Sample s of a pixel goes through its centre (`centres`)
/// or through the pixel's Owen-scrambled Sobol point s (its scramble from
/// FrameSeeds::pattern), eight pixels' at a time (owenSobol2DLanes). The (pixel,
/// sample) pairs go to the backend in batches of up to kTilePixels camera
/// rays, by sample index and then pixel: the whole tile at one index when
/// every pixel samples, else the few pixels still sampling at several
/// consecutive indices (neighbouring rays either way, so each batch's camera
/// and shadow rays stay coherent, and the batches are always full). A
/// pixel's samples are summed in index order, whatever the batches.
template <class Accel, class Integ>
void sampleTile(const Accel &accel, const Integ &integrator, const CameraRays &camera,
                const FrameSettings &settings, const tile_detail::TileRect &rect, uint32_t end,
                bool spreadLight, bool pairedStrata, bool centres,
                tile_detail::TileWork &work, RayCounts &counts) {
  if (centres) {
    // Pixel centres are sample 0 alone (end == 1; pairedStrata: 0 >> 1 is 0).
    sampleCentres(accel, integrator, camera, settings, rect, spreadLight, work, counts);
    return;
  }
  uint32_t begin = end;
  size_t sampling = 0; // work.pixelList[0, sampling): the pixels with samples to take
  const tile_detail::FrameSeeds seeds(settings.stream());
  // The positions' scramble seed: for Sobol positions and the path
  // tracer's stratified choices, not for a pass of pixel centres.
  const bool usesPattern = !centres || settings.integrator == IntegratorKind::Path;
  const bool pinhole = !camera.hasLens() && !camera.timed();
  rect.forEachPixel([&](size_t i, int x, int y) {
    work.sums[i] = Color();
    work.squares[i] = Color();
    work.taken[i] = 0;
    if (work.first[i] < end) {
      work.pixelList[sampling++] = static_cast<uint16_t>(i);
      begin = std::min(begin, work.first[i]);
      work.x[i] = x;
      work.y[i] = y;
      const uint64_t pixel = static_cast<uint64_t>(y) * settings.width + x;
      work.samplerKey[i] = Sampler::pixelKeyOf(seeds.key, pixel);
      if (usesPattern) work.pattern[i] = mix64(seeds.pattern ^ pixel);
      if (!centres) {
        const OwenScramble scramble = owenScramble(work.pattern[i]);
        work.shuffle[i] = scramble.shuffle;
        work.sx[i] = scramble.sx;
        work.sy[i] = scramble.sy;
      }
      if (camera.hasLens())
        work.lensPattern[i] = mix64(seeds.lens ^ pixel);
      if (camera.timed())
        work.timePattern[i] = mix64(seeds.time ^ pixel);
      if (spreadLight)
        work.stratumOffset[i] = static_cast<uint32_t>(mix64(seeds.stratum ^ pixel) >> 32);
    }
  });
  size_t rays = 0;
  auto trace = [&] {
    tile_detail::traceCameraRays(accel, integrator, work, rays, counts);
    for (size_t j = 0; j < rays; ++j) {
      const Color &c = work.colors[j];
      const size_t i = work.pixelOf[j];
      work.sums[i] += c;
      work.squares[i] += c * c;
      ++work.taken[i];
    }
    rays = 0;
  };
  for (uint32_t s = begin; s < end; ++s) {
    const uint32_t reversedS = owen_detail::reverseBits(s);
    for (size_t k = 0; k < sampling;) {
      // The next pixels taking sample s, and where in them it falls.
      uint16_t lane[kOwenLanes];
      size_t lanes = 0;
      for (; k < sampling && lanes < kOwenLanes; ++k) {
        const uint16_t i = work.pixelList[k];
        if (work.first[i] > s) continue;
        lane[lanes++] = i;
      }
      double u[kOwenLanes], v[kOwenLanes];
      if (centres) {
        std::fill_n(u, lanes, 0.5);
        std::fill_n(v, lanes, 0.5);
      } else if (lanes && size_t(lane[lanes - 1] - lane[0]) == lanes - 1) {
        // Consecutive pixels (the list is in order): their own rows.
        const size_t i = lane[0];
        owenSobol2DLanes(reversedS, {&work.shuffle[i], &work.sx[i], &work.sy[i]}, lanes, u, v);
      } else {
        OwenLanes scrambles;
        for (size_t l = 0; l < lanes; ++l)
          scrambles.set(l, {work.shuffle[lane[l]], work.sx[lane[l]], work.sy[lane[l]]});
        owenSobol2DLanes(reversedS, scrambles.rows(), lanes, u, v);
      }
      // A pinhole's rays for the lanes at once, where they fit the batch.
      const bool together = pinhole && rays + lanes <= tile_detail::kTilePixels;
      if (together) {
        for (size_t l = 0; l < lanes; ++l) {
          work.px[l] = work.x[lane[l]] + u[l];
          work.py[l] = work.y[lane[l]] + v[l];
        }
        camera.generateMany(work.px.data(), work.py.data(), lanes, &work.rays[rays]);
      }
      for (size_t l = 0; l < lanes; ++l) {
        const size_t i = lane[l];
        Sampler &sampler = work.samplers[rays];
        sampler = Sampler(work.samplerKey[i], s);
        // The path tracer's choices, stratified over the pixel's samples.
        if (settings.integrator == IntegratorKind::Path) sampler.stratify(s, work.pattern[i]);
        if (spreadLight)
          sampler.lightStratum = (pairedStrata ? s >> 1 : s) + work.stratumOffset[i];
        const double px = work.x[i] + u[l], py = work.y[i] + v[l];
        if (!pinhole) [[unlikely]]
          work.rays[rays] = tile_detail::lensOrTimedRay(camera, work.lensPattern[i],
                                                        work.timePattern[i], s, px, py, sampler);
        else if (!together)
          work.rays[rays] = camera.generate(px, py);
        work.pixelOf[rays] = static_cast<uint16_t>(i);
        if (++rays == tile_detail::kTilePixels) trace();
      }
    }
  }
  if (rays) trace();
}

/// Refines the tile's active pixels (each with only its centre sample) on
/// the tile's edge lattice (render/pixel_lattice.h), round by round, each
/// round's lattice points traced in batches of up to kTilePixels camera
/// rays (in the order the pixels' cells ask for them, so the batches stay
/// coherent). A point's sample stream is its own, keyed by its place in the
/// frame's lattice, so a point on the side of two tiles is the same in both.
template <class Accel, class Integ>
void refineTile(const Accel &accel, const Integ &integrator, const CameraRays &camera,
                const FrameSettings &settings, const tile_detail::TileRect &rect,
                SampleBuffer &buffer, tile_detail::TileWork &work, RayCounts &counts) {
  static thread_local PixelLattice lattice;
  static thread_local std::vector<PixelLattice::Point> points;
  const uint32_t cells = 1u << settings.adaptiveSettings.latticeDepth;
  lattice.reset(settings.adaptiveSettings.latticeDepth, rect.width(), rect.y1 - rect.y0);
  std::array<uint32_t, tile_detail::kTilePixels> bufferIndex;
  rect.forEachPixel([&](size_t, int x, int y) {
    if (!buffer.active(x, y)) return;
    const size_t b = buffer.index(x, y);
    const uint32_t p = lattice.add(x - rect.x0, y - rect.y0, buffer.mean(b), !buffer.filled(b));
    bufferIndex[p] = static_cast<uint32_t>(b);
  });
  // The frame's lattice: points (X, Y) = (x * cells + i, y * cells + j).
  const uint64_t frameKey = Sampler::frameKey(settings.stream() ^ 0x9e3779b97f4a7c15ULL);
  const uint64_t frameSide = static_cast<uint64_t>(settings.width) * cells + 1;
  const uint64_t x0 = static_cast<uint64_t>(rect.x0) * cells;
  const uint64_t y0 = static_cast<uint64_t>(rect.y0) * cells;
  const double step = lattice.step();
  while (lattice.pixels() > 0) {
    points.clear();
    lattice.pending(points);
    for (size_t k = 0; k < points.size(); k += tile_detail::kTilePixels) {
      const size_t n = std::min<size_t>(tile_detail::kTilePixels, points.size() - k);
      for (size_t j = 0; j < n; ++j) {
        const PixelLattice::Point &q = points[k + j];
        work.px[j] = rect.x0 + q.i * step;
        work.py[j] = rect.y0 + q.j * step;
        work.samplers[j] =
            Sampler(Sampler::pixelKeyOf(frameKey, (y0 + q.j) * frameSide + x0 + q.i), 0);
      }
      camera.generateMany(work.px.data(), work.py.data(), n, work.rays.data());
      tile_detail::traceCameraRays(accel, integrator, work, n, counts);
      for (size_t j = 0; j < n; ++j) lattice.set(points[k + j], work.colors[j]);
    }
    if (!lattice.judge(settings.adaptiveSettings.noiseThreshold)) break;
  }
  for (uint32_t p = 0; p < lattice.pixels(); ++p)
    buffer.setRefined(bufferIndex[p], lattice.colour(p), lattice.points(p));
}

/// The centre-first pass of a tile with --sparse-centres
/// (render/sparse_centres.h): the centres it traces, round by round, each
/// the ray and sample stream the plain centre-first pass gives it (so a
/// traced centre, and a centre just past the tile traced for its
/// neighbours, is the same as there); every pixel's centre, traced or
/// filled, goes to the buffer.
template <class Accel, class Integ>
void sparseCentreTile(const Accel &accel, const Integ &integrator, const CameraRays &camera,
                      const FrameSettings &settings, const tile_detail::TileRect &rect,
                      SampleBuffer &buffer, tile_detail::TileWork &work,
                      RayCounts &counts) {
  SparseCentres &sparse = tile_detail::threadSparseCentres();
  static thread_local std::vector<SparseCentres::Point> points;
  const uint64_t key = Sampler::frameKey(settings.stream());
  sparse.reset(rect.width(), rect.y1 - rect.y0, rect.x1 < settings.width ? 1 : 0,
               rect.y1 < settings.height ? 1 : 0);
  const double threshold = settings.adaptiveSettings.noiseThreshold;
  for (;;) {
    points.clear();
    if (!sparse.next(threshold, points)) break;
    for (size_t k = 0; k < points.size(); k += tile_detail::kTilePixels) {
      const size_t n = std::min<size_t>(tile_detail::kTilePixels, points.size() - k);
      for (size_t j = 0; j < n; ++j) {
        const int x = rect.x0 + points[k + j].x, y = rect.y0 + points[k + j].y;
        work.px[j] = x + 0.5;
        work.py[j] = y + 0.5;
        const uint64_t pixel = static_cast<uint64_t>(y) * settings.width + x;
        work.samplers[j] = Sampler(Sampler::pixelKeyOf(key, pixel), 0);
      }
      camera.generateMany(work.px.data(), work.py.data(), n, work.rays.data());
      tile_detail::traceCameraRays(accel, integrator, work, n, counts);
      for (size_t j = 0; j < n; ++j) sparse.set(points[k + j], work.colors[j]);
    }
  }
  rect.forEachPixel([&](size_t, int x, int y) {
    const int lx = x - rect.x0, ly = y - rect.y0;
    buffer.setCentre(buffer.index(x, y), sparse.colour(lx, ly), sparse.traced(lx, ly));
  });
}

/// Fills the film's depth, normal and albedo layers: a 4 x 4 grid of camera
/// rays through each pixel (cell centres, the same for any sampling), the
/// first hits averaged. Costs one camera ray per grid point and no shading.
template <class Accel, class Integ>
void renderAovs(const Accel &accel, const Integ &integrator, const Scene &scene,
                const CameraRays &camera, const FrameSettings &settings, Film &film) {
  constexpr int kGrid = 4;
  film.enableAovs();
  const Transform cameraFromWorld = scene.camera.worldFromCamera.inverse();
  const PixelWindow w = tile_detail::window(settings);
  tbb::parallel_for(tbb::blocked_range<int>(w.y0, w.y1), [&](const auto &rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = w.x0; x < w.x1; ++x) {
        double depth = 0;
        Vec3 normal;
        Color albedo;
        int hits = 0;
        for (int s = 0; s < kGrid * kGrid; ++s) {
          const Ray ray =
              camera.generate(x + (s % kGrid + 0.5) / kGrid, y + (s / kGrid + 0.5) / kGrid);
          Hit hit;
          if (!accel.intersect(ray, hit)) continue;
          ++hits;
          depth += cameraFromWorld.applyPoint(hit.p).z;
          Ray seen = ray; // on through perfect mirrors and glass (path tracer)
          if (!integrator.aovVertex(seen, hit)) {
            const Color &sky = scene.background; // seen in the mirror, at most 1
            albedo += Color(std::clamp(sky.r, 0.0, 1.0), std::clamp(sky.g, 0.0, 1.0),
                            std::clamp(sky.b, 0.0, 1.0));
            continue;
          }
          const Vec3 facing = dot(seen.d, hit.ng) < 0 ? hit.ns : -hit.ns;
          normal += normalize(cameraFromWorld.applyNormal(facing));
          albedo += integrator.albedo(hit);
        }
        Film::Aov &a = film.aov(x, y);
        constexpr double kInv = 1.0 / (kGrid * kGrid);
        a.z = hits ? static_cast<float>(depth / hits) : std::numeric_limits<float>::infinity();
        const double len = length(normal);
        const Vec3 n = len > 0 ? normal / len : Vec3();
        a.n[0] = static_cast<float>(n.x);
        a.n[1] = static_cast<float>(n.y);
        a.n[2] = static_cast<float>(n.z);
        a.albedo[0] = static_cast<float>(albedo.r * kInv);
        a.albedo[1] = static_cast<float>(albedo.g * kInv);
        a.albedo[2] = static_cast<float>(albedo.b * kInv);
      }
    }
  });
}

namespace tile_detail {

/// The calling thread's work arrays, one set for every pass of every frame,
/// whatever the integrator and backend: every thread of the process,
/// rendering or not, gets the thread-local block copied and zeroed when it
/// starts (a page fault and 4 KB zeroed per page, on the thread that starts
/// it), and a copy per integrator type and backend was most of it.
inline TileWork &threadTileWork() {
  static thread_local TileWork work;
  return work;
}

/// Runs `sample(rect, work, counts)` on every 16 x 16 tile of the frame,
/// in parallel (TBB), each thread with its own work arrays and ray counts;
/// `sample` returns false for a tile it left alone. Progress counts the
/// tiles sampled. The one tile loop of fixed and adaptive sampling.
template <class Integ, class Sample>
void forEachTile(const FrameSettings &settings, tbb::combinable<RayCounts> &perThread,
                 const ProgressFn &progress, Sample &&sample) {
  using Tiles = tbb::blocked_range<size_t>;
  const int tilesX = (settings.width + kTileSize - 1) / kTileSize;
  const int tilesY = (settings.height + kTileSize - 1) / kTileSize;
  const size_t tileCount = static_cast<size_t>(tilesX) * tilesY;
  std::atomic<size_t> tilesDone{0};
  tbb::parallel_for(Tiles(0, tileCount, 1), [&](const Tiles &r) {
    setFlushToZero();
    static_assert(kTilePixels <= Integ::kMaxTileRays);
    TileWork &work = threadTileWork();
    RayCounts &local = perThread.local();
    for (size_t tile = r.begin(); tile != r.end(); ++tile) {
      const TileRect rect(tile, tilesX, settings.width, settings.height);
      if (!sample(rect, work, local)) continue;
      const size_t done = ++tilesDone;
      if (progress) progress(done, tileCount);
    }
  });
}

} // namespace tile_detail

template <class Integ, class Accel>
void renderTiles(const Accel &accel, const Scene &scene, const ImageCache &images,
                 const FrameSettings &settings, Film &film, RayCounts &counts,
                 const ProgressFn &progress) {
  using namespace tile_detail;
  const bool spread = settings.lightSampling == LightSampling::Spread;
  const int n = settings.samples;
  const AdaptiveSettings &adaptive = settings.adaptiveSettings;
  // Spread: a light's cells are cut into min(shares, cells) shares. Fixed
  // sampling: one share per sample, so a pixel's n x n samples shade every
  // cell once. Adaptive: samples 2k and 2k+1 take the same share and the
  // first pass's pairs cover every share (kept from the estimate LRay used
  // before, whose two halves had to see every cell: it costs nothing, and
  // the adaptive figures of bench/README.md were measured with it).
  const uint32_t minSamples = static_cast<uint32_t>(std::max(1, adaptive.minSamples));
  const uint32_t maxSamples =
      static_cast<uint32_t>(std::max(adaptive.maxSamples, adaptive.minSamples));
  const uint32_t shares =
      !spread ? 1u
      : settings.adaptive ? std::max<uint32_t>(1, firstSobolPass(minSamples, maxSamples) / 2)
                          : static_cast<uint32_t>(n) * static_cast<uint32_t>(n);
  const bool pairedStrata = settings.adaptive;
  const Integ integrator(scene, accel, images,
                         {shares, settings.shadowSkips, settings.maxDepth, settings.clamp});
  const CameraRays camera(scene.camera, settings.width, settings.height, scene.motionSteps >= 2);
  const PixelWindow crop = window(settings);
  tbb::combinable<RayCounts> perThread;
  auto stopped = [&] { return settings.cancel && settings.cancel->load(); };
  // The Whitted integrator's samples are one stratified set per pixel; the
  // path tracer's are taken as independent (render/pixel_error.h).
  const SampleSet sampleSet = settings.integrator == IntegratorKind::Whitted
                                  ? SampleSet::Stratified
                                  : SampleSet::Independent;
  if (!settings.adaptive) {
    // Fixed sampling: n x n samples per pixel at the same Owen-scrambled
    // Sobol positions as adaptive sampling's (measured: lower RMSE than one
    // jittered sample per n x n stratum, at the same cost); one sample goes
    // through the pixel centre, as POV-Ray's does (lower RMSE than one
    // random position; figures in bench/HISTORY.md).
    const double invSamples = 1.0 / (static_cast<double>(n) * n);
    const uint32_t total = static_cast<uint32_t>(n) * static_cast<uint32_t>(n);
    forEachTile<Integ>(
        settings, perThread, progress,
        [&](const TileRect &rect, TileWork &work, RayCounts &local) {
          if (!meets(rect, crop)) return false;
          const size_t count = rect.pixels();
          std::fill_n(work.first.begin(), count, 0u);
          sampleTile(accel, integrator, camera, settings, rect, total, spread, false, n == 1, work,
                     local);
          rect.forEachPixel([&](size_t i, int x, int y) {
            film.setSamples(x, y, work.sums[i] * invSamples,
                            varianceOfMean(work.sums[i], work.squares[i], total), total,
                            sampleSet);
          });
          return true;
        });
    perThread.combine_each([&](const RayCounts &c) { counts += c; });
    if (settings.aovs) renderAovs(accel, integrator, scene, camera, settings, film);
    summarizeSampling(film);
    film.report.passes = 1;
    return;
  }

  // Adaptive: passes of Owen-scrambled Sobol samples; after each pass the
  // pixels below the noise threshold (and not next to a noisy one) stop.
  // --min-samples 1 starts with the centre-first pass: one sample through
  // each pixel centre (every light cell), the best single sample (as
  // POV-Ray's, and fixed sampling's at 1 x 1); a pixel stops there unless
  // it differs from a neighbour (SampleBuffer::centreContrast) or most of
  // its neighbours do, which is where edges and texture detail are. The
  // others drop their centre sample and go on with Sobol passes from 4.
  const bool centreFirst = minSamples == 1;
  const uint32_t firstSobol = firstSobolPass(minSamples, maxSamples);
  std::optional<Integ> allCells;
  if (centreFirst && shares > 1)
    allCells.emplace(scene, accel, images,
                     IntegratorOptions{1, settings.shadowSkips, settings.maxDepth, settings.clamp});
  const Integ &centreIntegrator = allCells ? *allCells : integrator;
  // The centre-first pass's options, for the Whitted integrator and not
  // for a lens or an open shutter: a lattice point or a filled centre has
  // no lens or time sample of its own (lua/README.md says so).
  const bool pinholeCentres = centreFirst && settings.integrator == IntegratorKind::Whitted &&
                              !camera.hasLens() && !camera.timed();
  // --edge-lattice: the pixels the centre-first pass flags are refined on
  // their lattices, shaded as the centres are (every light cell), in one
  // more pass.
  const bool lattice = pinholeCentres && adaptive.latticeDepth > 0;
  // --sparse-centres: the centre-first pass fills the centres between
  // traced ones that agree.
  const bool sparse = pinholeCentres && adaptive.sparseCentres && adaptive.noiseThreshold > 0;

  // A cropped render samples a margin around the window: a pixel's
  // neighbours decide whether it takes the next pass, so the missing
  // pixels beyond the margin change states one pixel further in per pass
  // (two in the centre-first pass's: its contrast, then its neighbours').
  // With a margin of the passes plus a tile, no tile holding window pixels
  // ever sees a changed state: its ray batches, and so its pixels, are
  // exactly those of the whole frame. The region is whole tiles.
  PixelWindow region{0, 0, settings.width, settings.height};
  if (!settings.crop.empty()) {
    const int margin = adaptivePasses(minSamples, maxSamples) + 2 + kTileSize;
    auto down = [](int v) { return std::max(0, v / kTileSize * kTileSize); };
    auto up = [](int v, int limit) {
      return std::min(limit, (v + kTileSize - 1) / kTileSize * kTileSize);
    };
    region = {down(crop.x0 - margin), down(crop.y0 - margin), up(crop.x1 + margin, settings.width),
              up(crop.y1 + margin, settings.height)};
  }
  SampleBuffer buffer(settings.width, settings.height, sampleSet, region.x0, region.y0, region.x1,
                      region.y1);
  const auto start = std::chrono::steady_clock::now();
  const bool timed = adaptive.timeLimit > 0;
  const auto deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(timed ? adaptive.timeLimit : 0));
  std::atomic<bool> timeUp{false}, cancelled{false};
  int passes = 0;
  // Whether a pass after the first leaves its next tile alone: the render
  // was cancelled or its time is up (noted for the report).
  auto haltsTile = [&] {
    if (stopped()) {
      cancelled = true;
      return true;
    }
    if (timed && std::chrono::steady_clock::now() >= deadline) {
      timeUp = true;
      return true;
    }
    return false;
  };
  // The live preview: the image of the passes so far.
  auto showPass = [&] {
    if (!settings.onPass || cancelled) return;
    Film sofar(settings.width, settings.height);
    buffer.writeTo(sofar);
    sofar.report.passes = passes;
    settings.onPass(sofar);
  };
  uint32_t target = minSamples; // maxSamples >= minSamples; 1: the centre-first pass
  for (int pass = 0;; ++pass) {
    forEachTile<Integ>(
        settings, perThread, progress,
        [&](const TileRect &rect, TileWork &work, RayCounts &local) {
          if (!buffer.anyActive(rect.x0, rect.y0, rect.x1, rect.y1)) return false;
          // The first pass always completes: every pixel needs a value.
          if (pass > 0 && haltsTile()) return false;
          if (pass == 0 && sparse) {
            sparseCentreTile(accel, centreIntegrator, camera, settings, rect, buffer, work, local);
          } else if (centreFirst && pass == 0) {
            rect.forEachPixel([&](size_t i, int x, int y) {
              work.first[i] = buffer.active(x, y) ? 0 : 1;
            });
            sampleTile(accel, centreIntegrator, camera, settings, rect, 1, false, false, true,
                       work, local);
            rect.forEachPixel([&](size_t i, int x, int y) {
              if (work.taken[i]) buffer.setCentre(buffer.index(x, y), work.sums[i]);
            });
          } else {
            rect.forEachPixel([&](size_t i, int x, int y) {
              const size_t p = buffer.index(x, y);
              work.first[i] = !buffer.active(x, y) ? target
                              : buffer.restart(p)  ? 0
                                                   : buffer.count(p);
            });
            sampleTile(accel, integrator, camera, settings, rect, target, spread, pairedStrata,
                       false, work, local);
            rect.forEachPixel([&](size_t i, int x, int y) {
              if (work.taken[i])
                buffer.add(buffer.index(x, y), work.sums[i], work.squares[i], work.taken[i]);
            });
          }
          return true;
        });
    ++passes;
    showPass();
    if (timeUp || cancelled || target >= maxSamples) break;
    if (buffer.updateActive(adaptive.noiseThreshold, maxSamples) == 0) break;
    if (timed && std::chrono::steady_clock::now() >= deadline) {
      timeUp = true;
      break;
    }
    if (stopped()) {
      cancelled = true;
      break;
    }
    if (lattice) {
      forEachTile<Integ>(
          settings, perThread, progress,
          [&](const TileRect &rect, TileWork &work, RayCounts &local) {
            if (!buffer.anyActive(rect.x0, rect.y0, rect.x1, rect.y1) || haltsTile())
              return false;
            refineTile(accel, centreIntegrator, camera, settings, rect, buffer, work, local);
            return true;
          });
      ++passes;
      showPass();
      break;
    }
    // Each pass adds half the samples taken so far (at least the first
    // Sobol pass's): the error falls by about a fifth per pass, and a
    // pixel overshoots its threshold by at most half its samples.
    const uint32_t step = std::max(firstSobol, target / 4 * 2);
    target = centreFirst && pass == 0 ? firstSobol : std::min(maxSamples, target + step);
  }
  perThread.combine_each([&](const RayCounts &c) { counts += c; });
  std::move(buffer).moveTo(film);
  if (settings.aovs) renderAovs(accel, integrator, scene, camera, settings, film);
  film.report.passes = passes;
  film.report.timeLimitHit = timeUp;
  film.report.cancelled = cancelled;
}

} // namespace lray
