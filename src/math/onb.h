// Pipeline: shared math. An orthonormal basis around a unit vector, for
// turning directions sampled about +z into world space.
#pragma once

#include "math/vec3.h"

#include <cmath>

namespace lray {

/// Tangents t and b with (t, b, n) orthonormal and right-handed, for a unit
/// n; continuous except at n.z = -1 (Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited").
inline void orthonormalBasis(const Vec3 &n, Vec3 &t, Vec3 &b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = Vec3(1 + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

/// The direction with coordinates (x, y, z) in the basis around n.
inline Vec3 fromBasis(const Vec3 &n, double x, double y, double z) {
  Vec3 t, b;
  orthonormalBasis(n, t, b);
  return t * x + b * y + n * z;
}

} // namespace lray
