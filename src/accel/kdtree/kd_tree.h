// Pipeline: acceleration (kd-tree backend). A SAH kd-tree over abstract
// primitives (triangles of one mesh, or the entities of a scene), built once
// and then traversed by many threads. Knows nothing of shapes: the caller
// supplies primitive bounds and a clipper at build time and an intersection
// callback at query time, so the same tree serves both levels of the
// two-level (instanced) kd-tree backend.
#pragma once

#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/packet_lanes.h"
#include "accel/kdtree/sah_cost_model.h"
#include "math/bounds.h"
#include "math/ray.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace lray {

/// Bounds of the part of primitive `prim` inside `box` (empty when none of
/// it is). Called only while building, for "perfect splits".
using KdClipFunction = std::function<Bounds3(uint32_t prim, const Bounds3 &box)>;

/// How a traversal walks the tree. Both visit every cell the ray's segment
/// touches, front to back, and give the same results.
enum class KdRays {
  /// Single rays in any order (secondary rays, their shadow rays): ordinary
  /// rays descend by the side of each plane their segment starts on.
  Incoherent,
  /// Rays that neighbour the previous one (a tile's camera rays and their
  /// shadow rays): the general loop, whose branches then predict well.
  Coherent,
};

/// Parameters of a kd-tree build.
struct KdBuildOptions {
  SahCostModel cost;
  /// Deepest allowed node; <= 0 picks 8 + 1.3 log2(N) (capped by the traversal stack).
  int maxDepth = 0;
  /// Nodes with at least this many primitives build their children in parallel.
  size_t parallelThreshold = 4096;
  /// Every leaf's list starts at a multiple of this (a power of two) in
  /// primIndices(), padded with copies of its last primitive, so per-leaf
  /// data kept in that order can be grouped in SIMD packets.
  uint32_t leafAlignment = 1;
};

/// Figures about a built tree.
struct KdTreeInfo {
  size_t nodes = 0;
  size_t leaves = 0;
  size_t emptyLeaves = 0;
  size_t primReferences = 0; ///< sum of leaf sizes (a primitive may sit in several leaves)
  size_t paddedReferences = 0; ///< primIndices() size (leaves padded to the alignment)
  int depth = 0;             ///< deepest node reached
  int maxDepth = 0;          ///< the limit the build used
};

/// A SAH kd-tree. An empty tree (no primitives) is valid: every ray misses.
class KdTree {
public:
  /// Deepest traversal stack; the build never exceeds it.
  static constexpr int kMaxDepth = 62;

  KdTree() = default;

  /// Builds over primitives with the given bounds (in the tree's space);
  /// primitives with empty or non-finite bounds are left out. SAH build in
  /// O(N log N): binned planes for large nodes, sorted events swept exactly
  /// (Wald & Havran 2006) for small ones; parallel with TBB.
  static KdTree build(std::span<const Bounds3> primBounds, const KdClipFunction &clip,
                      const KdBuildOptions &options = {});

  /// Walks the cells the ray crosses front to back, calling
  /// `bool test(uint32_t prim, double &tMax)` for each primitive of each
  /// leaf: the callback tests the primitive for t in (ray.tMin, tMax) and on
  /// a hit lowers tMax and returns true. Closest hit (AnyHit = false): stops
  /// once no later cell can hold a nearer hit; any hit: stops at the first.
  /// Returns whether the callback reported a hit. Ray in the tree's space.
  template <bool AnyHit, KdRays Rays = KdRays::Incoherent, class PrimTest>
  bool traverse(const Ray &ray, double &tMax, PrimTest &&test) const;

  /// The same walk, one call per non-empty leaf:
  /// `bool testLeaf(uint32_t offset, uint32_t count, double &tMax)` tests the
  /// leaf's references primIndices()[offset .. offset + count) (and any data
  /// the caller keeps in that order) as `test` above does one primitive.
  /// Rays: KdRays::Coherent walks by the general loop alone (which rays
  /// with a direction component of 0 or of extreme magnitude always take);
  /// it visits the same leaves in the same order as the descent of
  /// Incoherent rays, less a few the descent adds where a segment starts
  /// within a tiny margin of a plane (see kStartOriginRel).
  template <bool AnyHit, KdRays Rays = KdRays::Incoherent, class LeafTest>
  bool traverseLeaves(const Ray &ray, double &tMax, LeafTest &&testLeaf) const;

  /// Rays walked together by traversePacket.
  static constexpr int kPacketRays = 4;

  /// Up to kPacketRays rays (lane i: rays[i], where bit i of `lanes` is
  /// set) through the tree together: each lane visits the cells its own
  /// walk by the general loop visits, in the same order and with the same
  /// segment, so its results are those of traverseLeaves with
  /// KdRays::Coherent. One leaf call serves the lanes in that cell:
  /// `uint32_t testLeaf(uint32_t offset, uint32_t count, uint32_t lanes,
  /// double *tMax)` tests the leaf's references for each lane i of `lanes`
  /// with t in (rays[i].tMin, tMax[i]), lowers tMax[i] on a hit and returns
  /// the lanes that hit. The lanes share each node's load and step when
  /// their rays move the same way along every axis (rays to or from nearby
  /// points); otherwise each group of lanes that do walks together, a lane
  /// unlike the others on its own. Returns the lanes that hit (any hit: a
  /// lane stops at its first).
  template <bool AnyHit, class LeafTest>
  uint32_t traversePacket(const Ray *rays, uint32_t lanes, double *tMax,
                          LeafTest &&testLeaf) const;

  /// Bounds of all primitives (rounded outwards to float), tree space.
  const Bounds3 &bounds() const { return bounds_; }
  bool empty() const { return nodes_.empty(); }
  const KdTreeInfo &info() const { return info_; }
  /// Bytes held by nodes and primitive lists.
  size_t memoryBytes() const {
    return nodes_.capacity() * sizeof(KdNode) + primIndices_.capacity() * sizeof(uint32_t);
  }
  /// Node array (for tests that inspect the structure).
  const std::vector<KdNode> &nodes() const { return nodes_; }
  /// Primitives of a leaf (for tests).
  std::vector<uint32_t> leafPrims(const KdNode &leaf) const {
    auto first = primIndices_.begin() + leaf.primOffset();
    return {first, first + leaf.primCount()};
  }
  /// The leaves' primitive lists, one after another (leaf order), each
  /// padded to the build's leafAlignment.
  std::span<const uint32_t> primIndices() const { return primIndices_; }

  /// Relative slack on ray/plane parameters: every cell decision is widened
  /// by it, so rounding in t can never drop a cell the ray truly touches
  /// (no misses through vertices or edges lying on split planes).
  static constexpr double kSlack = 1e-9;

private:
  friend class KdTreeBuilder;

  // "Ordinary" rays, whose direction components all lie within
  // [kOrdinaryMin, kOrdinaryMax] in magnitude and whose origin's lie below
  // kOrdinaryMax, take the descent by the side of each plane on which the
  // segment's start lies; others (a component of 0: parallel to planes)
  // take the general loop.
  static constexpr double kOrdinaryMin = 1e-100, kOrdinaryMax = 1e100;
  // The margin that makes the start-side rule agree with the t rule.
  // Take a ray moving up axis a (d > 0; the other way is symmetric), the
  // segment start p = o + t0 d, u = 2^-53 and margin m = kStartOriginRel
  // |o| + kStartStepRel |t0 d| + kStartTiny. Computed p lies within 2.01u
  // (|o| + |t0 d|) of the exact start, lo = p - m within 1.01u (|p| + m)
  // more, so the exact start exceeds lo by D > 0.66e-15 |o| + 0.99e-8 |t0
  // d| + 0.99 kStartTiny (kStartOriginRel = 1e-15 is 9u, covering the
  // roundings). A split s < lo (compared exactly: floats are doubles) thus
  // has s - o < t0 d - D. For a plane beyond the origin, the general
  // loop's tHi = (s - o) / d (1 + kSlack) with at most 6 roundings is then
  // below t0, since D > 1.01 (kSlack + 6u) t0 |d| with 8x to spare; for a
  // plane at or behind it, tHi <= 0 <= t0 (for t0 = 0 strictly: s - o <=
  // -0.99 kStartTiny, and an ordinary ray's 1 / d keeps tPlane far from
  // underflow); for t0 < 0 the first argument holds. So wherever the
  // descent goes far only, the general loop does too. The margin is tiny
  // (1e-8 of the distance travelled), so extra cells are rare.
  static constexpr double kStartOriginRel = 1e-15, kStartStepRel = 1e-8, kStartTiny = 1e-30;

  static constexpr double kDoubleInf = std::numeric_limits<double>::infinity();
  // Smaller trees sit in the caches, where the general loop's well
  // predicted branches win: incoherent rays there take the general loop
  // (less time on bench_kd_rays at 10^2-10^3 triangles: bench/HISTORY.md).
  static constexpr size_t kDescentMinNodes = 4096;

  // A ray clipped to the root box, components in arrays (indexed by the
  // split axis at every node).
  struct RaySetup {
    double org[3], dir[3], invD[3];
    uint32_t dirNegative[3];
    double tEnter, tExit;
  };
  // Whether the ray may take the start-side descent (see kOrdinaryMin).
  static bool ordinary(const RaySetup &r) {
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      const double d = std::fabs(r.dir[a]);
      ok = ok && d >= kOrdinaryMin && d <= kOrdinaryMax && std::fabs(r.org[a]) <= kOrdinaryMax;
    }
    return ok;
  }
  // A cell waiting on the traversal stack: node and segment.
  struct Todo {
    uint32_t node;
    double tMin, tMax;
  };
  // False when the ray misses the root box (or the tree is empty).
  bool clipToBounds(const Ray &ray, double tMax, RaySetup &r) const;
  // The general loop: t-rule decisions at every node, any direction.
  template <bool AnyHit, class LeafTest>
  bool walkGeneral(const RaySetup &r, double &tMax, LeafTest &testLeaf) const;
  // The start-side descent of ordinary incoherent rays in trees of at
  // least kDescentMinNodes nodes.
  template <bool AnyHit, class LeafTest>
  bool descend(const RaySetup &r, double &tMax, LeafTest &testLeaf) const;

  // A packet's rays clipped to the root box, lane by lane (RaySetup's
  // fields as vectors).
  struct PacketSetup {
    packet_lanes::Lanes org[3], dir[3], invD[3], tEnter, tExit;
  };
  // clipToBounds for the lanes of `lanes` at once, the same operations lane
  // by lane: the lanes that cross the box (void for a lane with a
  // direction component of 0). Lanes outside `lanes` copy the first lane's
  // ray.
  uint32_t clipPacket(const Ray *rays, uint32_t lanes, const double *tMax, PacketSetup &p) const;

  // The packet walk of traversePacket over lanes whose rays all move the
  // same way along every axis (see there).
  template <bool AnyHit, class LeafTest>
  uint32_t walkPacket(const PacketSetup &p, const uint32_t *dirNegative, uint32_t lanes,
                      double *tMax, LeafTest &testLeaf) const;

  std::vector<KdNode> nodes_;
  std::vector<uint32_t> primIndices_;
  Bounds3 bounds_;
  KdTreeInfo info_;
};

template <bool AnyHit, KdRays Rays, class PrimTest>
bool KdTree::traverse(const Ray &ray, double &tMax, PrimTest &&test) const {
  return traverseLeaves<AnyHit, Rays>(ray, tMax, [&](uint32_t offset, uint32_t count,
                                                     double &tBest) {
    const uint32_t *prims = primIndices_.data() + offset;
    bool hit = false;
    for (uint32_t i = 0; i < count; ++i) {
      if (test(prims[i], tBest)) {
        hit = true;
        if (AnyHit) return true;
      }
    }
    return hit;
  });
}

// The ray against the root box (slab test). An axis the ray is parallel to
// only asks whether the origin lies within the slab: (lo - o) * inf would be
// NaN when the origin lies on the slab's face.
[[gnu::always_inline]] inline bool KdTree::clipToBounds(const Ray &ray, double tMax,
                                                        RaySetup &r) const {
  if (nodes_.empty()) return false;
  r.tEnter = ray.tMin;
  r.tExit = tMax;
  r.org[0] = ray.o.x, r.org[1] = ray.o.y, r.org[2] = ray.o.z;
  r.dir[0] = ray.d.x, r.dir[1] = ray.d.y, r.dir[2] = ray.d.z;
  for (int a = 0; a < 3; ++a) {
    const double d = r.dir[a], o = r.org[a];
    r.invD[a] = 1.0 / d;
    r.dirNegative[a] = d < 0 ? 1 : 0;
    if (d == 0) {
      if (o < bounds_.lo[a] || o > bounds_.hi[a]) return false;
      continue;
    }
    double tNear = (bounds_.lo[a] - o) * r.invD[a];
    double tFar = (bounds_.hi[a] - o) * r.invD[a];
    if (tNear > tFar) std::swap(tNear, tFar);
    r.tEnter = std::max(r.tEnter, tNear - std::fabs(tNear) * kSlack);
    r.tExit = std::min(r.tExit, tFar + std::fabs(tFar) * kSlack);
    if (!(r.tEnter <= r.tExit)) return false;
  }
  return true;
}

// Always inlined: as a call of its own (the kd-tree backend's mesh leaf
// test grew with its prefilter) it cost small scenes more instructions
// (bench/HISTORY.md, figures from source comments).
template <bool AnyHit, KdRays Rays, class LeafTest>
[[gnu::always_inline]] inline bool KdTree::traverseLeaves(const Ray &ray, double &tMax,
                                                        LeafTest &&testLeaf) const {
  RaySetup r;
  if (!clipToBounds(ray, tMax, r)) return false;
  if (Rays == KdRays::Incoherent && nodes_.size() >= kDescentMinNodes && ordinary(r)) {
    // The leaf test as a call of its own: inlined into the descent it
    // made incoherent rays on 10^5-10^6 triangles slower (bench/HISTORY.md).
    auto leafCall = [&testLeaf](uint32_t offset, uint32_t count, double &tBest)
                        __attribute__((noinline)) { return testLeaf(offset, count, tBest); };
    return descend<AnyHit>(r, tMax, leafCall);
  }
  return walkGeneral<AnyHit>(r, tMax, testLeaf);
}

template <bool AnyHit, class LeafTest>
[[gnu::noinline]] bool KdTree::descend(const RaySetup &r, double &tMax,
                                       LeafTest &testLeaf) const {
  // Ordinary rays descend from each cell to a leaf by the side of every
  // split plane on which their segment's start p = o + t0 d lies: one
  // comparison of the split with a per-segment threshold decides the step,
  // soon after the node's load, and the far side is rarely taken, so the
  // branch predicts well; the general loop decides late, after its t
  // arithmetic, and mispredicts often on incoherent rays. The side is the
  // near one unless the plane lies before p by more than a margin (then the
  // t rule agrees: see kStartOriginRel), so the descent enters every cell
  // the general loop enters, in the same order, with the same segment, and
  // a few more where p lies within the margin of a plane. The far children
  // to visit later are pushed by the general loop's t rule, without a
  // branch; empty leaves are popped. On bench_kd_rays (bumpy sphere of
  // 10^4-10^6 triangles) it took secondary rays less time than the general
  // loop, shadow rays to one light (neighbours in 8x8 blocks) less at 10^6
  // but a little more at 10^4 (bench/HISTORY.md).
  Todo stack[kMaxDepth + 2];
  int top = 0;
  uint32_t nodeIndex = 0;
  double t0 = r.tEnter, t1 = r.tExit;
  bool hit = false;
  const KdNode *nodes = nodes_.data();
  for (;;) {
    // farOnly at a node on axis a: split < lo[a] (ray moving up the axis)
    // or split > hi[a] (moving down); the other bound is infinite. (Double
    // thresholds: float ones, with a margin of two float roundings, put
    // many more leaves in the walks of a scene 3e5 from the origin:
    // bench/HISTORY.md.)
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double step = t0 * r.dir[a];
      const double p = r.org[a] + step;
      const double margin =
          kStartOriginRel * std::fabs(r.org[a]) + kStartStepRel * std::fabs(step) + kStartTiny;
      lo[a] = r.dir[a] > 0 ? p - margin : -kDoubleInf;
      hi[a] = r.dir[a] < 0 ? p + margin : kDoubleInf;
    }
    KdNode node = nodes[nodeIndex];
    while (!node.isLeaf()) {
      const int axis = node.axis();
      const double split = node.split();
      const bool farOnly = (split < lo[axis]) | (split > hi[axis]);
      const uint32_t below = node.childIndex();
      const uint32_t nearChild = below + r.dirNegative[axis];
      const uint32_t farChild = below + 1 - r.dirNegative[axis];
      const double tPlane = (split - r.org[axis]) * r.invD[axis];
      const double slack = std::fabs(tPlane) * kSlack;
      const double tLo = tPlane - slack, tHi = tPlane + slack;
      // Going near, the far side is needed by the general loop's rule (the
      // plane lies before t0, or the segment reaches it) unless it is an
      // empty leaf. Stored always, kept by moving the top.
      const bool pushFar =
          (!farOnly) & ((tHi < t0) | (tLo <= t1)) & (!nodes[farChild].isEmptyLeaf());
      stack[top] = {farChild, std::max(t0, tLo), t1};
      top += pushFar;
      // A branch (rarely taken, so well predicted) rather than a select:
      // the next node's load then starts before this step's arithmetic is
      // done. (Selects measured slower; so did passing over empty near
      // children here instead of popping them, at 10^5-10^6:
      // bench/HISTORY.md.) Going far, t0 stays:
      // the plane lies before it.
      if (farOnly) {
        nodeIndex = farChild;
      } else {
        t1 = std::min(t1, tHi);
        nodeIndex = nearChild;
      }
      node = nodes[nodeIndex];
    }
    const uint32_t count = node.primCount();
    if (count > 0 && testLeaf(node.primOffset(), count, tMax)) {
      hit = true;
      if (AnyHit) return true;
    }
    // Next cell from the stack; a hit (or, for any-hit queries, the end of
    // the segment) nearer than its entry ends the search.
    if (top == 0) break;
    --top;
    nodeIndex = stack[top].node;
    t0 = stack[top].tMin;
    t1 = stack[top].tMax;
    if (tMax < t0) break;
  }
  return hit;
}

template <bool AnyHit, class LeafTest>
[[gnu::always_inline]] inline bool KdTree::walkGeneral(const RaySetup &r, double &tMax,
                                                     LeafTest &testLeaf) const {
  Todo stack[kMaxDepth + 2];
  int top = 0;
  uint32_t nodeIndex = 0;
  double t0 = r.tEnter, t1 = r.tExit;
  bool hit = false;
  for (;;) {
    // A hit (or, for any-hit queries, the segment's end) nearer than this
    // cell's entry ends the search: later cells start later still.
    if (tMax < t0) break;
    const KdNode &node = nodes_[nodeIndex];
    if (!node.isLeaf()) {
      int axis = node.axis();
      double split = node.split();
      double o = r.org[axis];
      uint32_t below = node.childIndex(), above = below + 1;
      if (r.dir[axis] == 0) {
        // Parallel to the plane: one side, or both when lying in it
        // (primitives in the plane may have been put on either side).
        if (o < split) nodeIndex = below;
        else if (o > split) nodeIndex = above;
        else {
          stack[top++] = {above, t0, t1};
          nodeIndex = below;
        }
        continue;
      }
      // The near child holds the ray's line before the plane (t < tPlane),
      // the far child after it. The sign of split - o is exact, so a plane
      // behind the origin (tPlane < 0) is never widened to reach t >= 0; a
      // ray starting on the plane at t0 = 0 visits both sides.
      const double tPlane = (split - o) * r.invD[axis];
      const double slack = std::fabs(tPlane) * kSlack;
      const double tLo = tPlane - slack, tHi = tPlane + slack;
      const uint32_t nearChild = below + r.dirNegative[axis];
      const uint32_t farChild = above - r.dirNegative[axis];
      // The near side unless the cell starts beyond the plane; the far side
      // unless the cell ends before it (a NaN tPlane keeps the far side).
      const bool nearNeeded = tHi >= t0;
      const bool farNeeded = !nearNeeded || tLo <= t1;
      // The children sit side by side (one cache line): empty leaves among
      // them are skipped without a visit or a stack entry.
      const bool nearEmpty = nodes_[nearChild].isEmptyLeaf();
      const bool farEmpty = nodes_[farChild].isEmptyLeaf();
      if (nearNeeded && !nearEmpty) {
        if (farNeeded && !farEmpty) stack[top++] = {farChild, std::max(t0, tLo), t1};
        nodeIndex = nearChild;
        t1 = std::min(t1, tHi);
        continue;
      }
      if (farNeeded && !farEmpty) {
        nodeIndex = farChild;
        t0 = std::max(t0, tLo);
        continue;
      }
      // Nothing below this node: next cell from the stack.
    } else {
      const uint32_t count = node.primCount();
      if (count > 0 && testLeaf(node.primOffset(), count, tMax)) {
        hit = true;
        if (AnyHit) return true;
      }
    }
    if (top == 0) break;
    --top;
    nodeIndex = stack[top].node;
    t0 = stack[top].tMin;
    t1 = stack[top].tMax;
  }
  return hit;
}

[[gnu::always_inline]] inline uint32_t KdTree::clipPacket(const Ray *rays, uint32_t lanes,
                                                         const double *tMax,
                                                         PacketSetup &p) const {
  using packet_lanes::Lanes;
  const int firstLane = std::countr_zero(lanes);
  for (int i = 0; i < kPacketRays; ++i) {
    const int k = (lanes >> i & 1u) ? i : firstLane;
    const Ray &ray = rays[k];
    for (int a = 0; a < 3; ++a) {
      p.org[a][i] = ray.o[a];
      p.dir[a][i] = ray.d[a];
    }
    p.tEnter[i] = ray.tMin;
    p.tExit[i] = tMax[k];
  }
  Lanes slackFactor, one;
  packet_lanes::splat(kSlack, slackFactor);
  packet_lanes::splat(1.0, one);
  // A lane whose segment is empty after one axis stays so after the others
  // (its entry only grows, its exit only shrinks), as clipToBounds returns
  // there.
  for (int a = 0; a < 3; ++a) {
    Lanes lo, hi;
    packet_lanes::splat(bounds_.lo[a], lo);
    packet_lanes::splat(bounds_.hi[a], hi);
    p.invD[a] = one / p.dir[a];
    packet_lanes::clipToSlab(lo, hi, p.org[a], p.invD[a], slackFactor, p.tEnter, p.tExit);
  }
  return packet_lanes::bits(p.tEnter <= p.tExit) & lanes;
}

template <bool AnyHit, class LeafTest>
inline uint32_t KdTree::traversePacket(const Ray *rays, uint32_t lanes, double *tMax,
                                       LeafTest &&testLeaf) const {
  using packet_lanes::Lanes;
  using packet_lanes::Mask;
  if (nodes_.empty()) return 0;
  PacketSetup p;
  const uint32_t crossing = clipPacket(rays, lanes, tMax, p);
  // Rays parallel to a plane take the general loop's own branch and
  // clipToBounds' own test (their lanes of p are void).
  const Mask parallel = (p.dir[0] == Lanes{}) | (p.dir[1] == Lanes{}) | (p.dir[2] == Lanes{});
  RaySetup r[kPacketRays];
  uint32_t live = 0, hits = 0;
  if ((packet_lanes::bits(parallel) & lanes) != 0) {
    for (int i = 0; i < kPacketRays; ++i)
      if ((lanes >> i & 1u) && clipToBounds(rays[i], tMax[i], r[i])) live |= 1u << i;
  } else {
    live = crossing;
    if (live == 0) return 0;
    // Together: rays that move the same way along every axis, none out of
    // range (see kOrdinaryMin).
    Lanes tiny, huge;
    packet_lanes::splat(kOrdinaryMin, tiny);
    packet_lanes::splat(kOrdinaryMax, huge);
    Mask ordinary = ~Mask{};
    uint32_t dirNegative[3];
    bool together = std::popcount(live) > 1;
    for (int a = 0; a < 3; ++a) {
      Lanes d = p.dir[a], o = p.org[a];
      packet_lanes::clearSigns(d);
      packet_lanes::clearSigns(o);
      ordinary &= (d >= tiny) & (d <= huge) & (o <= huge);
      const uint32_t negative = packet_lanes::bits(p.dir[a] < Lanes{}) & live;
      together = together && (negative == 0 || negative == live);
      dirNegative[a] = negative != 0 ? 1 : 0;
    }
    together = together && (packet_lanes::bits(ordinary) & live) == live;
    if (together) return walkPacket<AnyHit>(p, dirNegative, live, tMax, testLeaf);
    // Else the lanes that move the same way as one another walk together,
    // a packet walk for each such group of two or more (rays from one
    // point to a light's cells may part on an axis), the others alone.
    uint32_t alone = live & ~packet_lanes::bits(ordinary);
    for (uint32_t rest = live & ~alone; rest != 0;) {
      const uint32_t first = rest & -rest;
      uint32_t group = rest;
      for (int a = 0; a < 3; ++a) {
        const uint32_t negative = packet_lanes::bits(p.dir[a] < Lanes{});
        dirNegative[a] = (negative & first) != 0 ? 1 : 0;
        group &= dirNegative[a] ? negative : ~negative;
      }
      rest &= ~group;
      if (std::popcount(group) > 1)
        hits |= walkPacket<AnyHit>(p, dirNegative, group, tMax, testLeaf);
      else
        alone |= group;
    }
    live = alone;
    for (int i = 0; i < kPacketRays; ++i) {
      if (!(live >> i & 1u)) continue;
      for (int a = 0; a < 3; ++a) {
        r[i].org[a] = p.org[a][i];
        r[i].dir[a] = p.dir[a][i];
        r[i].invD[a] = p.invD[a][i];
        r[i].dirNegative[a] = p.dir[a][i] < 0 ? 1 : 0;
      }
      r[i].tEnter = p.tEnter[i];
      r[i].tExit = p.tExit[i];
    }
  }
  for (int i = 0; i < kPacketRays; ++i) {
    if (!(live >> i & 1u)) continue;
    // walkGeneral hands the leaf test tMax[i] itself (by reference), so the
    // lane's entry of the array is the one it lowers.
    auto laneLeaf = [&testLeaf, tMax, i](uint32_t offset, uint32_t count, double &) {
      return testLeaf(offset, count, 1u << i, tMax) != 0;
    };
    if (walkGeneral<AnyHit>(r[i], tMax[i], laneLeaf)) hits |= 1u << i;
  }
  return hits;
}

template <bool AnyHit, class LeafTest>
uint32_t KdTree::walkPacket(const PacketSetup &p, const uint32_t *dirNegative, uint32_t lanes,
                            double *tMax, LeafTest &testLeaf) const {
  // walkGeneral's steps, lane by lane, on one node at a time: a lane goes
  // to each child that its own walk would visit, with the same segment;
  // the packet visits a child when any lane does. A cell waiting on the
  // stack keeps its lanes and their segments. The lanes' arithmetic runs
  // in one vector (one AVX register; SSE2 pairs on the baseline target),
  // operation for operation as walkGeneral's (no NaN can arise: no
  // direction component is 0), so every decision is the same.
  using packet_lanes::Lanes;
  using packet_lanes::Mask;
  static_assert(kPacketRays == packet_lanes::kWidth);
  struct alignas(32) PacketTodo {
    Lanes tMin, tMax;
    uint32_t node, lanes;
  };
  const Lanes(&org)[3] = p.org, (&invD)[3] = p.invD;
  Lanes t0 = p.tEnter, t1 = p.tExit;
  Lanes slackFactor;
  packet_lanes::splat(kSlack, slackFactor);
  PacketTodo stack[kMaxDepth + 2];
  int top = 0;
  uint32_t nodeIndex = 0, cellLanes = lanes, hits = 0, done = 0;
  for (;;) {
    // A lane whose hit lies before this cell's entry is done with it, as
    // walkGeneral stops there. Any-hit lanes are done at their first hit,
    // and a cell's entry never lies past their segment's end (t0 <= t1 <=
    // tExit <= tMax holds for each lane of a cell: the near child's t1 is
    // at least t0 where it is needed, the far child's t0 at most t1), so
    // they skip the test.
    uint32_t in = cellLanes & ~done;
    if (!AnyHit) {
      Lanes limit;
      packet_lanes::load(tMax, limit);
      in &= packet_lanes::bits(t0 <= limit);
    }
    if (in != 0) {
      const KdNode node = nodes_[nodeIndex];
      if (!node.isLeaf()) {
        const int axis = node.axis();
        Lanes split;
        packet_lanes::splat(node.split(), split);
        const uint32_t below = node.childIndex();
        const uint32_t nearChild = below + dirNegative[axis];
        const uint32_t farChild = below + 1 - dirNegative[axis];
        const Lanes tPlane = (split - org[axis]) * invD[axis];
        Lanes slack = tPlane;
        packet_lanes::clearSigns(slack);
        slack *= slackFactor;
        const Lanes tLo = tPlane - slack, tHi = tPlane + slack;
        const Mask nearNeeded = tHi >= t0;
        const Mask farNeeded = (tHi < t0) | (tLo <= t1);
        uint32_t nearLanes = packet_lanes::bits(nearNeeded);
        uint32_t farLanes = packet_lanes::bits(farNeeded);
        nearLanes = nodes_[nearChild].isEmptyLeaf() ? 0 : nearLanes & in;
        farLanes = nodes_[farChild].isEmptyLeaf() ? 0 : farLanes & in;
        // std::min(t1, tHi) and std::max(t0, tLo), as walkGeneral takes them.
        const Lanes nearT1 = tHi < t1 ? tHi : t1, farT0 = tLo > t0 ? tLo : t0;
        if (nearLanes != 0) {
          if (farLanes != 0) {
            PacketTodo &todo = stack[top++];
            todo.node = farChild;
            todo.lanes = farLanes;
            todo.tMin = farT0;
            todo.tMax = t1;
          }
          nodeIndex = nearChild;
          cellLanes = nearLanes;
          t1 = nearT1;
          continue;
        }
        if (farLanes != 0) {
          nodeIndex = farChild;
          cellLanes = farLanes;
          t0 = farT0;
          continue;
        }
        // Nothing below this node for any lane: next cell from the stack.
      } else if (node.primCount() > 0) {
        const uint32_t found = testLeaf(node.primOffset(), node.primCount(), in, tMax);
        hits |= found;
        if (AnyHit) {
          done |= found;
          if (done == lanes) return hits;
        }
      }
    }
    if (top == 0) break;
    const PacketTodo &todo = stack[--top];
    nodeIndex = todo.node;
    cellLanes = todo.lanes;
    t0 = todo.tMin;
    t1 = todo.tMax;
  }
  return hits;
}

} // namespace lray
