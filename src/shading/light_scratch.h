// Pipeline: shading. The shading equation's per-thread working arrays
// (integrator.h): a tile's hits and its light loop's shadow rays, and a
// single point's rounds of an area light. One set per thread for either
// backend: every thread the process starts, rendering or not, gets the
// thread-local block copied and zeroed on the thread that starts it (a
// page fault and 4 KB zeroed per page), and a set per backend doubled it.
#pragma once

#include "math/color.h"
#include "math/ray.h"
#include "math/spawn.h"
#include "math/vec3.h"
#include "shading/light_lanes.h"
#include "shading/shadow_batch.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace lray {

struct Material;

/// What shading needs of a hit before any ray is traced (also a vertex of
/// the path tracer, path_integrator.h): Integrator::Surface.
struct HitSurface {
  const Material *m = nullptr;
  bool entering = false; ///< the ray arrives from the geometric normal's side
  Vec3 n, dir, v;        ///< N (facing the ray), normalize(ray.d), V
  Color pigment;
};

/// A light sample's shadow ray waiting to be traced: the point it lights
/// (`ray` indexes the points being lit) and where the sample lies as seen
/// from it.
struct PendingLight {
  /// The unit direction to the sample, N.L and the light it brings.
  struct Dir {
    Vec3 l;
    double nl;
    Color color;
  };
  uint32_t ray;
  Dir dir;
};

/// Most camera rays of one shadeTile call (Integrator::kMaxTileRays).
inline constexpr size_t kShadeTileRays = 256;
static_assert(LightLanes::kMax == kShadeTileRays);
/// directLight's rounds of an area light taken together (a batch).
inline constexpr size_t kPointRounds = 64;

/// shadeTile's arrays: a tile's surfaces, their light so far and the light
/// loop's shadow rays.
struct TileLightScratch {
  std::array<HitSurface, kShadeTileRays> surface;
  std::array<Color, kShadeTileRays> lightSum;
  std::array<PendingLight, kShadeTileRays> pending;
  std::array<Ray, kShadeTileRays> shadowRays;
  std::array<uint8_t, kShadeTileRays> blocked;
  std::array<SpawnOrigins, kShadeTileRays> origins;
  std::array<Vec3, kShadeTileRays> targets;
  LightLanes lanes;
  // On the heap: a thread's static TLS comes out of its stack, and the
  // batch is most of a megabyte. Not zeroed (new, not make_unique): a
  // light of few cells touches only the first pages of its arrays.
  std::unique_ptr<ShadowBatch> batch{new ShadowBatch};
};

/// directLight's arrays: room for kPointRounds of an area light's rounds
/// at once.
struct PointLightScratch {
  std::array<PendingLight, kPointRounds> pending;
  std::array<Ray, kPointRounds> shadowRays;
  std::array<uint8_t, kPointRounds> blocked;
  std::array<Vec3, kPointRounds> targets;
};

/// The calling thread's arrays (made on its first call).
inline TileLightScratch &threadTileLightScratch() {
  static thread_local TileLightScratch scratch;
  return scratch;
}
inline PointLightScratch &threadPointLightScratch() {
  static thread_local PointLightScratch scratch;
  return scratch;
}

} // namespace lray
