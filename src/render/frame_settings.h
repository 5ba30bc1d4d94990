// Pipeline: render. What one frame is rendered at, and how progress is
// reported; shared by the renderer and the backends that run its tile loop.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace lray {

/// How light transport is computed (render/backends.cpp pairs each with
/// each backend).
enum class IntegratorKind {
  Whitted, ///< lua/README.md, "The shading equation": lights, mirror and refraction rays
  Path,    ///< lua/README.md, "Light transport": a physically based path tracer
};
constexpr size_t kIntegratorKinds = 2;

/// How a pixel sample lights a point under an area light of K cells.
enum class LightSampling {
  All,    ///< every sample shades every cell (lua/README.md, "Lights")
  Spread, ///< the samples of a pixel share the cells out (Integrator's lightShares)
};

/// Progressive sampling: passes of Owen-scrambled Sobol samples until
/// every pixel's error estimate is below the threshold, or the time is up.
struct AdaptiveSettings {
  double noiseThreshold = 0; ///< 0: no pixel stops early (a time limit ends the render)
  int minSamples = 16;       ///< samples per pixel of the first pass (even, or 1: centre first)
  int maxSamples = 1024;     ///< no pixel takes more
  double timeLimit = 0;      ///< seconds; 0: none
  /// --edge-lattice: the pixels the centre-first pass finds at an edge are
  /// refined on a lattice of cells down to 2^-latticeDepth of a pixel wide
  /// (render/pixel_lattice.h) instead of by Sobol passes; 0: Sobol passes.
  int latticeDepth = 0;
  /// --sparse-centres: the centre-first pass fills the centres between
  /// traced ones that agree instead of tracing them
  /// (render/sparse_centres.h).
  bool sparseCentres = false;
};

/// A pixel rectangle [x0, x1) x [y0, y1) of a frame.
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool operator==(const PixelWindow &) const = default;
};

struct FrameSettings {
  int width = 800;
  int height = 600;
  int samples = 1;    ///< n: n x n samples per pixel (fixed sampling; 1: the pixel centre)
  int frameIndex = 0; ///< part of the random-stream key
  /// Also part of it (--seed): another seed gives independent samples of
  /// the same picture; 0 is the default stream.
  uint32_t seed = 0;
  /// The frame's random-stream key: frameIndex, and the seed above it.
  uint64_t stream() const {
    return static_cast<uint64_t>(static_cast<uint32_t>(frameIndex)) |
           (static_cast<uint64_t>(seed) << 32);
  }
  IntegratorKind integrator = IntegratorKind::Whitted;
  int maxDepth = 8; ///< Path: the most scattering events of a path
  double clamp = 0; ///< Path: a sample's largest component at most this (0: no clamp)
  bool adaptive = false; ///< progressive passes as `adaptiveSettings` says, instead of n x n
  AdaptiveSettings adaptiveSettings;
  LightSampling lightSampling = LightSampling::All;
  /// Also fill the film's depth, normal and albedo layers (Film::aov).
  bool aovs = false;
  /// Skip shadow rays nothing can block (shading/shadow_shaft.h): the same
  /// image either way; off only to measure or to check that.
  bool shadowSkips = true;
  /// Render only this window of the frame (--crop, --tile); empty: all of
  /// it. Its pixels get the same values as in a render of the whole frame:
  /// the 16 x 16 tiles it touches are sampled whole (the same ray batches),
  /// and adaptive sampling runs on a margin around it as wide as its
  /// passes can carry a neighbour's influence.
  PixelWindow crop;
  /// Adaptive sampling: called after each pass with the image so far (the
  /// live preview shows it refining); not called by fixed sampling.
  std::function<void(const class Film &)> onPass;
  /// Set by another thread to stop an adaptive render at the next tile
  /// boundary (its first pass always completes; fixed sampling ignores it).
  const std::atomic<bool> *cancel = nullptr;
};

/// Called after each finished tile with (tiles done, tiles total), from
/// worker threads: must be thread-safe. An adaptive render reports each
/// pass's tiles (the total is the pass's).
using ProgressFn = std::function<void(size_t, size_t)>;

constexpr int kTileSize = 16;

} // namespace lray
