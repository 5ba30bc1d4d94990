// Pipeline: script -> scene description. The value behind Lua's Transform:
// the forward 3x4 matrix only (96 bytes instead of Transform's 264), so the
// millions of temporaries a procedural scene makes (Translate(p) * Scale(s))
// are small and cheap to compose. The inverse is computed once, when the
// plain model is built (toTransform).
#pragma once

#include "math/transform.h"

#include <algorithm>
#include <cmath>

namespace lray::lua {

/// An affine map, row-major 3x4: p' = M[:, 0:3] p + M[:, 3].
struct Affine {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  static Affine from(const Transform &t) {
    Affine a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) a.m[i][j] = t.matrix().m[i][j];
    return a;
  }

  /// The full Transform (matrix and inverse); singular() as Transform decides.
  Transform toTransform() const {
    Mat4 mat = Mat4::identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) mat.m[i][j] = m[i][j];
    return Transform::fromMatrix(mat);
  }

  /// `a * b` applies b first, then a.
  Affine operator*(const Affine &b) const {
    Affine r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j)
        r.m[i][j] = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j];
      r.m[i][3] += m[i][3];
    }
    return r;
  }

  /// Not invertible (relative to the size of its entries) or not finite;
  /// the same test Transform::fromMatrix applies.
  bool singular() const {
    double scale = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) scale = std::max(scale, std::fabs(m[i][j]));
      if (!std::isfinite(m[i][3])) return true;
    }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return !std::isfinite(det) || scale == 0 || std::fabs(det) <= 1e-300 ||
           std::fabs(det) <= scale * scale * scale * 1e-14;
  }

  bool operator==(const Affine &o) const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j)
        if (m[i][j] != o.m[i][j]) return false;
    return true;
  }
};

} // namespace lray::lua
