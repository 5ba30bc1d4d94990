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
  /// When in the open shutter the ray is traced, in [0, 1] (lua/README.md,
  /// "Motion blur"); 0 without motion blur. Secondary rays keep their
  /// camera ray's time.
  float time = 0;

  Vec3 at(double t) const { return o + d * t; }
};

} // namespace lray
