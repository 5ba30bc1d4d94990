// Pipeline: acceleration (kd-tree backend). The top level of a scene of a
// few bounded entities (the bench's glass and pigments scenes: a floor and
// four shapes) as a list of boxes: each ray tests the entities whose boxes
// its segment crosses (nearest box first when it looks for the nearest
// hit, in the scene's order for a shadow ray). The top-level tree's walk
// (ray set-up, a handful of nodes, a mailbox) cost such scenes more than
// the box tests do; a nearest hit is the same either way. Also the few
// entities a run of camera rays may meet in a larger scene (ray_fan.h).
#pragma once

#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/packet_lanes.h"
#include "math/bounds.h"
#include "math/ray.h"

#include <algorithm>
#include <array>
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
    for (uint32_t i = 0; i < boxes.size(); ++i) add(boxes[i], i);
  }
  /// Keeps `box` as entity `id`'s, after those kept before; at most
  /// kMaxInstances.
  void add(const Bounds3 &box, uint32_t id) {
    const uint32_t i = count_++;
    boxes_[i] = box;
    ids_[i] = id;
    all_.extend(box);
    Group &g = groups_[i / kLanes];
    for (int a = 0; a < 3; ++a) {
      g.lo[a][i % kLanes] = box.lo[a];
      g.hi[a][i % kLanes] = box.hi[a];
    }
  }
  bool empty() const { return count_ == 0; }
  bool full() const { return count_ == kMaxInstances; }

  /// test(id, tBest) for each entity whose box the segment (tMin, tBest)
  /// of `ray` crosses; whether any test returned true. AnyHit: in the
  /// order they were kept, until a test returns true. Else, for the
  /// nearest hit (a test lowers tBest to the hit it finds): nearest box
  /// first, until the next box begins past tBest.
  template <bool AnyHit, class Test>
  [[gnu::always_inline]] bool forEachCrossed(const Ray &ray, double &tBest, Test &&test) const {
    const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
    const double invD[3] = {1 / d[0], 1 / d[1], 1 / d[2]};
    // Rays that miss every box (the background) are told by one test.
    if (!crosses(all_, o, d, invD, ray.tMin, tBest)) return false;
    bool hit = false;
    if (d[0] == 0 || d[1] == 0 || d[2] == 0) { // a parallel axis: box by box
      for (uint32_t i = 0; i < count_; ++i) {
        if (!crosses(boxes_[i], o, d, invD, ray.tMin, tBest)) continue;
        if (test(ids_[i], tBest)) {
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
    for (uint32_t g = 0; g * kLanes < count_; ++g)
      crossed |= entries(groups_[g], o, invD, ray.tMin, tBest, enter + kLanes * g) << kLanes * g;
    crossed &= (1u << count_) - 1;
    if (AnyHit) {
      for (; crossed != 0; crossed &= crossed - 1) {
        const uint32_t i = static_cast<uint32_t>(__builtin_ctz(crossed));
        if (enter[i] <= tBest && test(ids_[i], tBest)) return true;
      }
      return false;
    }
    // The nearest hit: boxes by their entry, nearest first (the first kept
    // on equal entries), until the next one begins past the nearest hit so
    // far. A floor's box, crossed behind the shape a ray meets, is then
    // not tested at all.
    while (crossed != 0) {
      uint32_t i = static_cast<uint32_t>(__builtin_ctz(crossed));
      for (uint32_t rest = crossed & (crossed - 1); rest != 0; rest &= rest - 1) {
        const uint32_t k = static_cast<uint32_t>(__builtin_ctz(rest));
        if (enter[k] < enter[i]) i = k;
      }
      if (!(enter[i] <= tBest)) break;
      crossed &= ~(1u << i);
      hit |= test(ids_[i], tBest);
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

  // Fixed arrays: intersectCoherent keeps a list of its own for each run of
  // rays (RayFan).
  std::array<Bounds3, kMaxInstances> boxes_;
  std::array<uint32_t, kMaxInstances> ids_;
  std::array<Group, kMaxInstances / kLanes> groups_;
  uint32_t count_ = 0;
  Bounds3 all_; ///< their union
};

} // namespace lray
