// Pipeline: acceleration (kd-tree backend). Rays from one origin (a run of
// a tile's camera rays through a pinhole) bounded together: which of a few
// boxes any of them may cross is told once for the run, so that each ray
// tests only those (KdTreeAccelerator::intersectCoherent). Where the
// camera sees a few of a scene's entities in each tile, most runs keep one
// or none.
#pragma once

#include "accel/kdtree/kd_tree.h"
#include "math/bounds.h"
#include "math/ray.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lray {

class RayFan {
public:
  /// False unless every ray starts at rays[0]'s origin, no direction
  /// component is 0 or changes sign between them, and no bound is NaN.
  bool gather(const Ray *rays, size_t n) {
    if (n == 0) return false;
    const Ray &first = rays[0];
    double dLo[3], dHi[3];
    for (int a = 0; a < 3; ++a) {
      o_[a] = first.o[a];
      dLo[a] = dHi[a] = first.d[a];
    }
    tMin_ = first.tMin;
    tMax_ = first.tMax;
    for (size_t i = 0; i < n; ++i) {
      const Ray &r = rays[i];
      if (!(r.o == first.o) || std::isnan(r.tMin) || std::isnan(r.tMax)) return false;
      for (int a = 0; a < 3; ++a) {
        if (!(r.d[a] > 0 ? first.d[a] > 0 : r.d[a] < 0 && first.d[a] < 0)) return false;
        dLo[a] = std::min(dLo[a], r.d[a]);
        dHi[a] = std::max(dHi[a], r.d[a]);
      }
      tMin_ = std::min(tMin_, r.tMin);
      tMax_ = std::max(tMax_, r.tMax);
    }
    // The extremes of the rays' own 1 / d, as FlatInstances's slab test
    // takes it: 1 / d falls as d rises on either side of 0, and division
    // rounds monotonically.
    for (int a = 0; a < 3; ++a) {
      invLo_[a] = 1 / dHi[a];
      invHi_[a] = 1 / dLo[a];
    }
    return true;
  }

  /// False only where FlatInstances's slab test of `box` fails for every
  /// ray of the fan: a ray's entry and exit on an axis are the products of
  /// the same difference with its 1 / d, and rounding is monotonic, so they
  /// lie between the products with the fan's extremes of 1 / d; its tMin
  /// and tMax between the fan's. Twice the slab test's slack covers its
  /// own rounding.
  bool mayCross(const Bounds3 &box) const {
    double tEnter = tMin_, tExit = tMax_;
    for (int a = 0; a < 3; ++a) {
      const double lo = box.lo[a] - o_[a], hi = box.hi[a] - o_[a];
      // Entering through lo where the direction is positive, else hi.
      const double nearSide = invLo_[a] > 0 ? lo : hi, farSide = invLo_[a] > 0 ? hi : lo;
      const double tNear = std::min(nearSide * invLo_[a], nearSide * invHi_[a]);
      const double tFar = std::max(farSide * invLo_[a], farSide * invHi_[a]);
      tEnter = std::max(tEnter, tNear - std::fabs(tNear) * (2 * KdTree::kSlack));
      tExit = std::min(tExit, tFar + std::fabs(tFar) * (2 * KdTree::kSlack));
    }
    return !(tEnter > tExit);
  }

private:
  double o_[3] = {}, invLo_[3] = {}, invHi_[3] = {};
  double tMin_ = 0, tMax_ = 0;
};

} // namespace lray
