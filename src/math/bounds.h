// Pipeline: geometry. Axis-aligned bounding boxes in world (or object) space.
#pragma once

#include "math/vec3.h"

#include <limits>

namespace lray {

/// An axis-aligned box; empty when lo > hi on any axis.
struct Bounds3 {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};

  Bounds3() = default;
  Bounds3(const Vec3 &a, const Vec3 &b) : lo(min(a, b)), hi(max(a, b)) {}

  void extend(const Vec3 &p) { lo = min(lo, p); hi = max(hi, p); }
  void extend(const Bounds3 &b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  Vec3 diagonal() const { return hi - lo; }
  Vec3 center() const { return (lo + hi) * 0.5; }
  double surfaceArea() const {
    if (empty()) return 0;
    Vec3 d = diagonal();
    return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  int maxExtentAxis() const {
    Vec3 d = diagonal();
    return d.x > d.y ? (d.x > d.z ? 0 : 2) : (d.y > d.z ? 1 : 2);
  }
};

} // namespace lray
