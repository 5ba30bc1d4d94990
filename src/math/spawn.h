// Pipeline: geometry. Where secondary rays start: the hit point pushed off
// the surface along the geometric normal by the bound on its own error
// (scales with the magnitude of the hit coordinates; no fixed epsilon).
#pragma once

#include "math/hit.h"
#include "math/ray.h"

#include <cmath>
#include <limits>

namespace lray {

/// The hit point moved to the side of the surface that `dir` points into,
/// far enough that the surface cannot be re-hit by a ray leaving along `dir`.
inline Vec3 offsetRayOrigin(const Hit &hit, const Vec3 &dir) {
  double d = hit.pError * (std::fabs(hit.ng.x) + std::fabs(hit.ng.y) + std::fabs(hit.ng.z));
  Vec3 offset = hit.ng * d;
  if (dot(dir, hit.ng) < 0) offset = -offset;
  Vec3 p = hit.p + offset;
  // Round away from the surface so the rounding of the sum cannot undo the offset.
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0) p[i] = std::nextafter(p[i], std::numeric_limits<double>::infinity());
    else if (offset[i] < 0) p[i] = std::nextafter(p[i], -std::numeric_limits<double>::infinity());
  }
  return p;
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

} // namespace lray
