// Pipeline: geometry. Where secondary rays start: the hit point pushed off
// the surface along the geometric normal by the bound on its own error
// (scales with the magnitude of the hit coordinates; no fixed epsilon).
#pragma once

#include "math/hit.h"
#include "math/next_double.h"
#include "math/ray.h"

#include <cmath>
#include <limits>

namespace lray {

namespace spawn_detail {

/// The hit point's push off its surface: along ng, by the bound on the
/// point's error measured across ng's components.
inline Vec3 errorOffset(const Hit &hit) {
  double d = hit.pError * (std::fabs(hit.ng.x) + std::fabs(hit.ng.y) + std::fabs(hit.ng.z));
  return hit.ng * d;
}

/// `sum` (a coordinate of p + offset) rounded away from p by one ulp.
[[gnu::always_inline]] inline double roundedAway(double sum, double offset) {
  if (offset > 0) return nextUp(sum);
  if (offset < 0) return nextDown(sum);
  return sum;
}

/// p + offset, each coordinate rounded away from p so that the rounding of
/// the sum cannot undo the offset. Always inline: the light loop calls it
/// twice a point, and GCC stopped inlining it when that loop grew (1.6 %
/// more instructions on the 2011 `light` example). Coordinate by
/// coordinate, not p[i] in a loop: indexed, the point lived on the stack,
/// written in 8-byte pieces and read back in a 16-byte one, a
/// store-forwarding stall on every shadow ray.
[[gnu::always_inline]] inline Vec3 pushedOff(const Vec3 &from, const Vec3 &offset) {
  const Vec3 p = from + offset;
  return {roundedAway(p.x, offset.x), roundedAway(p.y, offset.y), roundedAway(p.z, offset.z)};
}

/// The shadow ray from `o` to `target` (t in (0, 1)), written field by
/// field into its place (see spawnRayTo below).
inline void writeShadowRay(const Vec3 &o, const Vec3 &target, float time, Ray &ray) {
  ray.o = o;
  ray.d = target - o;
  ray.tMin = 0;
  ray.tMax = 1;
  ray.time = time;
}

} // namespace spawn_detail

/// The hit point moved to the side of the surface that `dir` points into,
/// far enough that the surface cannot be re-hit by a ray leaving along `dir`.
inline Vec3 offsetRayOrigin(const Hit &hit, const Vec3 &dir) {
  Vec3 offset = spawn_detail::errorOffset(hit);
  if (dot(dir, hit.ng) < 0) offset = -offset;
  return spawn_detail::pushedOff(hit.p, offset);
}

/// Both of offsetRayOrigin's answers for a hit: for directions on the side
/// ng points to (front) and for the others (back). Many shadow rays leave
/// one point (an area light's cells): they pick one instead of each
/// computing it again.
struct SpawnOrigins {
  Vec3 front, back;
};

inline SpawnOrigins spawnOrigins(const Hit &hit) {
  const Vec3 offset = spawn_detail::errorOffset(hit);
  return {spawn_detail::pushedOff(hit.p, offset), spawn_detail::pushedOff(hit.p, -offset)};
}

/// A secondary ray leaving the surface in direction `dir`.
inline Ray spawnRay(const Hit &hit, const Vec3 &dir) {
  return {offsetRayOrigin(hit, dir), dir, 0, std::numeric_limits<double>::infinity(), hit.time};
}

/// A shadow ray from the surface that ends at `target` (t in (0, 1)).
inline Ray spawnRayTo(const Hit &hit, const Vec3 &target) {
  Vec3 o = offsetRayOrigin(hit, target - hit.p);
  return {o, target - o, 0, 1, hit.time};
}

/// ray = spawnRayTo(hit, target), from the hit's origins (spawnOrigins(hit)).
/// Written field by field into its place in a batch: a Ray built on the
/// stack and copied there was read back in 16-byte pieces across its
/// 8-byte stores, a store-forwarding stall on every shadow ray.
inline void spawnRayTo(const SpawnOrigins &origins, const Hit &hit, const Vec3 &target, Ray &ray) {
  spawn_detail::writeShadowRay(dot(target - hit.p, hit.ng) < 0 ? origins.back : origins.front,
                               target, hit.time, ray);
}

/// ray = spawnRayTo(hit, target), written field by field into its place
/// in a batch (see above): for a point with one shadow ray, which pushes
/// its origin off to the one side it needs.
inline void spawnRayTo(const Hit &hit, const Vec3 &target, Ray &ray) {
  spawn_detail::writeShadowRay(offsetRayOrigin(hit, target - hit.p), target, hit.time, ray);
}

} // namespace lray
