// Pipeline: acceleration (kd-tree backend). The top level of a scene of a
// few bounded entities (the bench's glass and pigments scenes: a floor and
// four shapes) as a list of boxes: each ray tests, in the scene's order,
// the entities whose boxes its segment crosses. The top-level tree's walk
// (ray set-up, a handful of nodes, a mailbox) cost such scenes more than
// the box tests do; a nearest hit is the same either way.
#pragma once

#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/packet_lanes.h"
#include "math/bounds.h"
#include "math/ray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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
    groups_.resize((boxes.size() + kLanes - 1) / kLanes);
    for (size_t i = 0; i < boxes.size(); ++i) {
      Group &g = groups_[i / kLanes];
      for (int a = 0; a < 3; ++a) {
        g.lo[a][i % kLanes] = boxes[i].lo[a];
        g.hi[a][i % kLanes] = boxes[i].hi[a];
      }
    }
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
    if (d[0] == 0 || d[1] == 0 || d[2] == 0) { // a parallel axis: box by box
      for (uint32_t i = 0; i < boxes_.size(); ++i) {
        if (!crosses(boxes_[i], o, d, invD, ray.tMin, tBest)) continue;
        if (test(i, tBest)) {
          hit = true;
          if (AnyHit) return true;
        }
      }
      return hit;
    }
    // Every box's entry t at once; a box is tested while its entry lies
    // before its exit and the nearest hit so far.
    alignas(32) double enter[kMaxInstances];
    uint32_t crossed = 0;
    for (size_t g = 0; g < groups_.size(); ++g)
      crossed |= entries(groups_[g], o, invD, ray.tMin, tBest, enter + kLanes * g) << kLanes * g;
    crossed &= (1u << boxes_.size()) - 1;
    for (; crossed != 0; crossed &= crossed - 1) {
      const uint32_t i = static_cast<uint32_t>(__builtin_ctz(crossed));
      if (!(enter[i] <= tBest)) continue;
      if (test(i, tBest)) {
        hit = true;
        if (AnyHit) return true;
      }
    }
    return hit;
  }

private:
  static constexpr int kLanes = packet_lanes::kWidth;
  using Lanes = packet_lanes::Lanes;
  /// Four boxes, axis by axis (lanes past the last box stay empty).
  struct Group {
    Lanes lo[3] = {}, hi[3] = {};
  };

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

  /// crosses() for a group's four boxes, lane by lane with the same
  /// operations (no direction component is 0 here): bit k set where box k
  /// is crossed; its entry t in enter[k].
  [[gnu::always_inline]] static uint32_t entries(const Group &g, const double (&o)[3],
                                                 const double (&invD)[3], double tMin,
                                                 double tMax, double *enter) {
    Lanes tEnter = Lanes{} + tMin, tExit = Lanes{} + tMax, slack;
    packet_lanes::splat(KdTree::kSlack, slack);
    for (int a = 0; a < 3; ++a) {
      Lanes origin, inverse;
      packet_lanes::splat(o[a], origin);
      packet_lanes::splat(invD[a], inverse);
      packet_lanes::clipToSlab(g.lo[a], g.hi[a], origin, inverse, slack, tEnter, tExit);
    }
    std::memcpy(enter, &tEnter, sizeof tEnter);
    return packet_lanes::bits(tEnter <= tExit);
  }

  std::vector<Bounds3> boxes_;
  std::vector<Group> groups_;
  Bounds3 all_; ///< their union
};

} // namespace lray
