// Pipeline: shared math. A ray with its valid parametric interval.
#pragma once

#include "math/vec3.h"

#include <limits>

namespace lray {

/// A ray o + t d, valid for t in (tMin, tMax). d need not be unit length;
/// distances t are in units of |d|.
struct Ray {
  Vec3 o;
  Vec3 d;
  double tMin = 0;
  double tMax = std::numeric_limits<double>::infinity();

  Vec3 at(double t) const { return o + d * t; }
};

} // namespace lray
