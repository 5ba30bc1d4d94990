// Pipeline: acceleration (kd-tree backend). The top level of a scene of a
// few bounded entities (the bench's glass and pigments scenes: a floor and
// four shapes) as a list of boxes: each ray tests, in the scene's order,
// the entities whose boxes its segment crosses. The top-level tree's walk
// (ray set-up, a handful of nodes, a mailbox) cost such scenes more than
// the box tests do; a nearest hit is the same either way.
#pragma once

#include "accel/kdtree/kd_tree.h"
#include "math/bounds.h"
#include "math/ray.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {

class FlatInstances {
public:
  /// The most entities kept as a list; more walk the top-level tree.
  static constexpr size_t kMaxInstances = 8;

  FlatInstances() = default;
  /// Entity i's box is boxes[i]; none kept (empty()) beyond kMaxInstances.
  explicit FlatInstances(const std::vector<Bounds3> &boxes) {
    if (boxes.size() > kMaxInstances) return;
    boxes_ = boxes;
    for (const Bounds3 &b : boxes) all_.extend(b);
  }
  bool empty() const { return boxes_.empty(); }

  /// test(i, tBest) for each entity i whose box the segment (tMin, tBest)
  /// of `ray` crosses, in index order; AnyHit: until a test returns true.
  /// Whether any test did.
  template <bool AnyHit, class Test>
  [[gnu::always_inline]] bool forEachCrossed(const Ray &ray, double &tBest, Test &&test) const {
    const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
    const double invD[3] = {1 / d[0], 1 / d[1], 1 / d[2]};
    // Rays that miss every box (the background) are told by one test.
    if (!crosses(all_, o, d, invD, ray.tMin, tBest)) return false;
    bool hit = false;
    for (uint32_t i = 0; i < boxes_.size(); ++i) {
      if (!crosses(boxes_[i], o, d, invD, ray.tMin, tBest)) continue;
      if (test(i, tBest)) {
        hit = true;
        if (AnyHit) return true;
      }
    }
    return hit;
  }

private:
  /// KdTree::clipToBounds' slab test (the same slack), on one box.
  [[gnu::always_inline]] static bool crosses(const Bounds3 &box, const double (&o)[3],
                                             const double (&d)[3], const double (&invD)[3],
                                             double tEnter, double tExit) {
    const double lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) { // parallel: (lo - o) * inf is NaN on the slab's face
        if (o[a] < lo[a] || o[a] > hi[a]) return false;
        continue;
      }
      double tNear = (lo[a] - o[a]) * invD[a];
      double tFar = (hi[a] - o[a]) * invD[a];
      if (tNear > tFar) std::swap(tNear, tFar);
      tEnter = std::max(tEnter, tNear - std::fabs(tNear) * KdTree::kSlack);
      tExit = std::min(tExit, tFar + std::fabs(tFar) * KdTree::kSlack);
      if (!(tEnter <= tExit)) return false;
    }
    return true;
  }

  std::vector<Bounds3> boxes_;
  Bounds3 all_; ///< their union
};

} // namespace lray
