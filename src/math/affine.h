// Pipeline: geometry (internal). Inline affine products on a Transform's
// matrices for the per-ray paths (Transform's own methods live in another
// translation unit and would not inline there).
#pragma once

#include "math/transform.h"
#include "math/vec3.h"

namespace lray {

/// m * (p, 1).
inline Vec3 affinePoint(const Mat4 &mat, const Vec3 &p) {
  const auto &m = mat.m;
  return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
          m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
          m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}

/// m * (v, 0).
inline Vec3 affineVector(const Mat4 &mat, const Vec3 &v) {
  const auto &m = mat.m;
  return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
          m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
          m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

/// A normal through `inv` = the inverse of the point transform: inv^T n.
inline Vec3 affineNormal(const Mat4 &inv, const Vec3 &n) {
  const auto &m = inv.m;
  return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
          m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
          m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
}

/// v scaled to unit length (one division).
inline Vec3 unitVector(const Vec3 &v) { return v * (1 / length(v)); }

} // namespace lray
