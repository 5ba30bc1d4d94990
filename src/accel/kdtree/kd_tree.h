// Pipeline: acceleration (kd-tree backend). A SAH kd-tree over abstract
// primitives (triangles of one mesh, or the entities of a scene), built once
// and then traversed by many threads. Knows nothing of shapes: the caller
// supplies primitive bounds and a clipper at build time and an intersection
// callback at query time, so the same tree serves both levels of the
// two-level (instanced) kd-tree backend.
#pragma once

#include "accel/kdtree/kd_node.h"
#include "accel/kdtree/sah_cost_model.h"
#include "geometry/bounds.h"
#include "math/ray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

namespace lray {

/// Bounds of the part of primitive `prim` inside `box` (empty when none of
/// it is). Called only while building, for "perfect splits".
using KdClipFunction = std::function<Bounds3(uint32_t prim, const Bounds3 &box)>;

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
  template <bool AnyHit, class PrimTest>
  bool traverse(const Ray &ray, double &tMax, PrimTest &&test) const;

  /// The same walk, one call per non-empty leaf:
  /// `bool testLeaf(uint32_t offset, uint32_t count, double &tMax)` tests the
  /// leaf's references primIndices()[offset .. offset + count) (and any data
  /// the caller keeps in that order) as `test` above does one primitive.
  template <bool AnyHit, class LeafTest>
  bool traverseLeaves(const Ray &ray, double &tMax, LeafTest &&testLeaf) const;

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

private:
  friend class KdTreeBuilder;

  // Relative slack on ray/plane parameters: every cell decision is widened
  // by it, so rounding in t can never drop a cell the ray truly touches
  // (no misses through vertices or edges lying on split planes).
  static constexpr double kSlack = 1e-9;

  std::vector<KdNode> nodes_;
  std::vector<uint32_t> primIndices_;
  Bounds3 bounds_;
  KdTreeInfo info_;
};

template <bool AnyHit, class PrimTest>
bool KdTree::traverse(const Ray &ray, double &tMax, PrimTest &&test) const {
  return traverseLeaves<AnyHit>(ray, tMax, [&](uint32_t offset, uint32_t count, double &tBest) {
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

// Always inlined: as a call of its own (the kd-tree backend's mesh leaf
// test grew with its prefilter) it cost small scenes 5 % more instructions.
template <bool AnyHit, class LeafTest>
[[gnu::always_inline]] inline bool KdTree::traverseLeaves(const Ray &ray, double &tMax,
                                                        LeafTest &&testLeaf) const {
  if (nodes_.empty()) return false;

  // Ray against the root box (slab test). An axis the ray is parallel to only
  // asks whether the origin lies within the slab: (lo - o) * inf would be NaN
  // when the origin lies on the slab's face.
  double tEnter = ray.tMin, tExit = tMax;
  // Components in arrays: indexed by the split axis at every node.
  const double org[3] = {ray.o.x, ray.o.y, ray.o.z};
  const double dir[3] = {ray.d.x, ray.d.y, ray.d.z};
  double invD[3];
  uint32_t dirNegative[3];
  for (int a = 0; a < 3; ++a) {
    double d = dir[a], o = org[a];
    invD[a] = 1.0 / d;
    dirNegative[a] = d < 0 ? 1 : 0;
    if (d == 0) {
      if (o < bounds_.lo[a] || o > bounds_.hi[a]) return false;
      continue;
    }
    double tNear = (bounds_.lo[a] - o) * invD[a];
    double tFar = (bounds_.hi[a] - o) * invD[a];
    if (tNear > tFar) std::swap(tNear, tFar);
    tEnter = std::max(tEnter, tNear - std::fabs(tNear) * kSlack);
    tExit = std::min(tExit, tFar + std::fabs(tFar) * kSlack);
    if (!(tEnter <= tExit)) return false;
  }

  struct Todo {
    uint32_t node;
    double tMin, tMax;
  };
  Todo stack[kMaxDepth + 2];
  int top = 0;
  uint32_t nodeIndex = 0;
  double t0 = tEnter, t1 = tExit;
  bool hit = false;
  for (;;) {
    // A hit (or, for any-hit queries, the segment's end) nearer than this
    // cell's entry ends the search: later cells start later still.
    if (tMax < t0) break;
    const KdNode &node = nodes_[nodeIndex];
    if (!node.isLeaf()) {
      int axis = node.axis();
      double split = node.split();
      double o = org[axis];
      uint32_t below = node.childIndex(), above = below + 1;
      if (dir[axis] == 0) {
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
      const double tPlane = (split - o) * invD[axis];
      const double slack = std::fabs(tPlane) * kSlack;
      const double tLo = tPlane - slack, tHi = tPlane + slack;
      const uint32_t nearChild = below + dirNegative[axis];
      const uint32_t farChild = above - dirNegative[axis];
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

} // namespace lray
