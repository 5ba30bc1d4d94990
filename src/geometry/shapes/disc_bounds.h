// Pipeline: geometry (internal). World bounds of a placed unit disc, for the
// shapes built from discs (Cylinder, Cone).
#pragma once

#include "math/transform.h"
#include "math/bounds.h"

#include <cmath>

namespace lray {

/// Bounds of the image of the unit disc {x^2 + z^2 <= 1, y = y0}: centre
/// M (0, y0, 0), half-extent along world axis i = |(M_i0, M_i2)|.
inline Bounds3 discBounds(const Mat4 &mat, double y0) {
  const auto &m = mat.m;
  Vec3 c = affinePoint(mat, {0, y0, 0});
  Vec3 e{std::hypot(m[0][0], m[0][2]), std::hypot(m[1][0], m[1][2]), std::hypot(m[2][0], m[2][2])};
  return {c - e, c + e};
}

} // namespace lray
