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
  static constexpr int kLanes = 4;
  // 32-byte vectors, whose passing differs between the baseline and AVX
  // ABIs: no function here takes or returns one (-Wpsabi).
  using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));
  using Mask = int64_t __attribute__((vector_size(kLanes * sizeof(int64_t))));
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
    Lanes tEnter = Lanes{} + tMin, tExit = Lanes{} + tMax;
    for (int a = 0; a < 3; ++a) {
      const Lanes tLo = (g.lo[a] - o[a]) * invD[a], tHi = (g.hi[a] - o[a]) * invD[a];
      const Mask swap = tLo > tHi;
      const Lanes tNear = swap ? tHi : tLo, tFar = swap ? tLo : tHi;
      // std::fabs: the sign bit cleared.
      Mask nearBits, farBits;
      std::memcpy(&nearBits, &tNear, sizeof tNear);
      std::memcpy(&farBits, &tFar, sizeof tFar);
      nearBits &= ~(Mask{} + INT64_MIN);
      farBits &= ~(Mask{} + INT64_MIN);
      Lanes absNear, absFar;
      std::memcpy(&absNear, &nearBits, sizeof absNear);
      std::memcpy(&absFar, &farBits, sizeof absFar);
      const Lanes nearSlack = tNear - absNear * KdTree::kSlack;
      const Lanes farSlack = tFar + absFar * KdTree::kSlack;
      tEnter = tEnter < nearSlack ? nearSlack : tEnter; // std::max
      tExit = farSlack < tExit ? farSlack : tExit;      // std::min
    }
    std::memcpy(enter, &tEnter, sizeof tEnter);
    const Mask in = tEnter <= tExit;
    uint32_t bits = 0;
    for (int k = 0; k < kLanes; ++k) bits |= static_cast<uint32_t>(in[k] != 0) << k;
    return bits;
  }

  std::vector<Bounds3> boxes_;
  std::vector<Group> groups_;
  Bounds3 all_; ///< their union
};

} // namespace lray
