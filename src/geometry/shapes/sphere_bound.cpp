#include "geometry/shapes/sphere_bound.h"

#include <cmath>

namespace lray {

namespace {

/// An upper bound of the largest eigenvalue of G = L^T L (L the linear part
/// of `m`), so of the square of L's largest stretch: G's largest absolute
/// row sum (Gershgorin). Exact for a rotation and scaling by the same factor
/// on every axis, where it is what a sphere is placed by.
double largestStretchSq(const Mat4 &m) {
  double bound = 0;
  for (int j = 0; j < 3; ++j) {
    double row = 0;
    for (int k = 0; k < 3; ++k)
      row += std::fabs(m.m[0][j] * m.m[0][k] + m.m[1][j] * m.m[1][k] + m.m[2][j] * m.m[2][k]);
    bound = std::fmax(bound, row);
  }
  return bound * (1 + 1e-9); // its own rounding
}

} // namespace

SphereBound::SphereBound(const Transform &worldFromObject) {
  const Mat4 &m = worldFromObject.matrix();
  const double radiusSq = largestStretchSq(m);
  // 1 / r_min^2 <= the inverse's largest stretch squared.
  const double inverseSq = largestStretchSq(worldFromObject.inverseMatrix());
  centre_ = {m.m[0][3], m.m[1][3], m.m[2][3]};
  const double farSq = kFar * kFar / inverseSq;
  if (!(std::isfinite(radiusSq) && std::isfinite(farSq) && farSq > 0 &&
        radiusSq * inverseSq <= kMaxStretch * kMaxStretch && dot(centre_, centre_) < farSq))
    return; // settles nothing
  radiusSq_ = radiusSq * (1 + kClearMargin);
  farSq_ = farSq;
}

} // namespace lray
