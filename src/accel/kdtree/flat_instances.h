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
#include "math/ray_lanes.h"
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

  /// How start() found a ray: it crosses no box; a component of its
  /// direction is 0 (boxes are then tested one by one, forEachCrossed); or
  /// its Walk holds the boxes it crosses.
  enum class Start { None, Parallel, Boxes };
  /// One ray's boxes: each crossed box's entry t, and which are left.
  struct Walk {
    alignas(32) double enter[kMaxInstances];
    uint32_t crossed = 0;
  };

  /// The boxes the segment (tMin, tBest) of `ray` crosses, into `walk`
  /// where the answer is Start::Boxes.
  [[gnu::always_inline]] Start start(const Ray &ray, double tBest, Walk &walk) const {
    const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
    const double invD[3] = {1 / d[0], 1 / d[1], 1 / d[2]};
    // Rays that miss every box (the background) are told by one test.
    if (!crosses(all_, o, d, invD, ray.tMin, tBest)) return Start::None;
    if (d[0] == 0 || d[1] == 0 || d[2] == 0) return Start::Parallel;
    // Every box's entry t at once; a box is tested while its entry lies
    // before its exit and the nearest hit so far.
    uint32_t crossed = 0;
    for (uint32_t g = 0; g * kLanes < count_; ++g)
      crossed |= entries(groups_[g], o, invD, ray.tMin, tBest, walk.enter + kLanes * g)
                 << kLanes * g;
    walk.crossed = crossed & ((1u << count_) - 1);
    return Start::Boxes;
  }

  /// start() of four rays at once, each with tBest its own tMax (rays[k],
  /// k in `open`; the others read any ray): the rays' fields in lanes,
  /// each box's slab test of the four (the same operations, lane by lane:
  /// the same entries and answers). A ray with a direction component 0
  /// takes start() alone.
  static constexpr int kRays = packet_lanes::kWidth;
  [[gnu::always_inline]] void start(const Ray *const (&rays)[kRays], uint32_t open,
                                    Walk (&walks)[kRays], Start (&how)[kRays]) const {
    lanes::RayLanes r;
    lanes::loadRays(rays, r);
    const Lanes one = Lanes{} + 1.0;
    const Lanes invD[3] = {one / r.dx, one / r.dy, one / r.dz};
    const Lanes origin[3] = {r.ox, r.oy, r.oz};
    const uint32_t parallel =
        packet_lanes::bits((r.dx == 0.0) | (r.dy == 0.0) | (r.dz == 0.0)) & open;
    Lanes slack;
    packet_lanes::splat(KdTree::kSlack, slack);
    // Whether each ray's segment (tMin, tMax) crosses `box`; its entry t.
    auto clip = [&](const Bounds3 &box, Lanes &tEnter) {
      tEnter = r.tMin;
      Lanes tExit = r.tMax;
      for (int a = 0; a < 3; ++a) {
        Lanes lo, hi;
        packet_lanes::splat(box.lo[a], lo);
        packet_lanes::splat(box.hi[a], hi);
        packet_lanes::clipToSlab(lo, hi, origin[a], invD[a], slack, tEnter, tExit);
      }
      return packet_lanes::bits(tEnter <= tExit);
    };
    Lanes tEnter;
    const uint32_t any = clip(all_, tEnter) & open & ~parallel;
    uint32_t crossed[packet_lanes::kWidth] = {};
    if (any != 0)
      for (uint32_t b = 0; b < count_; ++b) {
        const uint32_t in = clip(boxes_[b], tEnter);
        for (int k = 0; k < kRays; ++k) {
          walks[k].enter[b] = tEnter[k];
          crossed[k] |= (in >> k & 1u) << b;
        }
      }
    for (int k = 0; k < kRays; ++k) {
      if (!(open >> k & 1u)) continue;
      if (parallel >> k & 1u) {
        how[k] = start(*rays[k], rays[k]->tMax, walks[k]);
        continue;
      }
      how[k] = any >> k & 1u ? Start::Boxes : Start::None;
      walks[k].crossed = crossed[k];
    }
  }

  /// For the nearest hit: the walk's next box (its index; id() names its
  /// entity), nearest entry first (the first kept on equal entries), or -1
  /// once the next begins past tBest (the nearest hit so far) or none is
  /// left. A floor's box, crossed behind the shape a ray meets, is then not
  /// tested at all.
  [[gnu::always_inline]] int next(Walk &walk, double tBest) const {
    if (walk.crossed == 0) return -1;
    uint32_t i = static_cast<uint32_t>(__builtin_ctz(walk.crossed));
    for (uint32_t rest = walk.crossed & (walk.crossed - 1); rest != 0; rest &= rest - 1) {
      const uint32_t k = static_cast<uint32_t>(__builtin_ctz(rest));
      if (walk.enter[k] < walk.enter[i]) i = k;
    }
    if (!(walk.enter[i] <= tBest)) {
      walk.crossed = 0;
      return -1;
    }
    walk.crossed &= ~(1u << i);
    return static_cast<int>(i);
  }
  /// The entity of box `i`.
  uint32_t id(int i) const { return ids_[i]; }

  /// test(id, tBest) for each entity whose box the segment (tMin, tBest)
  /// of `ray` crosses; whether any test returned true. AnyHit: in the
  /// order they were kept, until a test returns true. Else, for the
  /// nearest hit (a test lowers tBest to the hit it finds): in next()'s
  /// order.
  template <bool AnyHit, class Test>
  [[gnu::always_inline]] bool forEachCrossed(const Ray &ray, double &tBest, Test &&test) const {
    Walk walk;
    const Start how = start(ray, tBest, walk);
    if (how == Start::None) return false;
    bool hit = false;
    if (how == Start::Parallel) { // box by box
      const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
      const double invD[3] = {1 / d[0], 1 / d[1], 1 / d[2]};
      for (uint32_t i = 0; i < count_; ++i) {
        if (!crosses(boxes_[i], o, d, invD, ray.tMin, tBest)) continue;
        if (test(ids_[i], tBest)) {
          hit = true;
          if (AnyHit) return true;
        }
      }
      return hit;
    }
    if (AnyHit) {
      for (uint32_t crossed = walk.crossed; crossed != 0; crossed &= crossed - 1) {
        const uint32_t i = static_cast<uint32_t>(__builtin_ctz(crossed));
        if (walk.enter[i] <= tBest && test(ids_[i], tBest)) return true;
      }
      return false;
    }
    for (int i; (i = next(walk, tBest)) >= 0;) hit |= test(ids_[i], tBest);
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
