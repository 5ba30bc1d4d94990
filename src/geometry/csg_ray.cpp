// Pipeline: geometry. See csg_ray.h.
#include "geometry/csg_ray.h"

#include "math/transform.h"
#include "geometry/csg_tree.h"
#include "geometry/shape.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace lray {

namespace {

/// One entry into or exit from a leaf along the ray's line.
struct Crossing {
  double t;       ///< world-ray parameter (the sort key)
  double tObject; ///< the same point in the leaf's shifted object ray (for its hit)
  uint32_t leaf;
  int part;       ///< the leaf's surface part; -1 for an end at infinity
  bool entering;
};

bool before(const Crossing &a, const Crossing &b) {
  if (a.t != b.t) return a.t < b.t;
  if (a.leaf != b.leaf) return a.leaf < b.leaf;
  return a.entering < b.entering; // a leaf's exit before its next entry
}

/// Per-thread working arrays: no allocation once a thread has seen its
/// largest tree.
struct Scratch {
  std::vector<Crossing> crossings;
  std::vector<int32_t> count;  ///< per node: children inside (a Difference: subtracted ones)
  std::vector<uint8_t> baseIn; ///< per node: a Difference's first child is inside
  std::vector<uint8_t> leafIn; ///< per leaf
  std::vector<uint8_t> keptBefore, keptAfter;
};

/// Whether the whole line of `ray` meets the box (t unbounded).
bool lineMeetsBox(const Ray &ray, const Bounds3 &b) {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    double o = ray.o[axis], d = ray.d[axis];
    if (d == 0) {
      if (o < b.lo[axis] || o > b.hi[axis]) return false;
      continue;
    }
    double inv = 1 / d;
    double t0 = (b.lo[axis] - o) * inv, t1 = (b.hi[axis] - o) * inv;
    if (t0 > t1) std::swap(t0, t1);
    // NaN from an infinite box face times 0 is no constraint.
    if (t0 > lo) lo = t0;
    if (t1 < hi) hi = t1;
  }
  return lo <= hi;
}

class Sweep {
public:
  Sweep(const CsgTree &tree, Scratch &s) : tree_(tree), s_(s) {
    s_.count.assign(tree.nodes.size(), 0);
    s_.baseIn.assign(tree.nodes.size(), 0);
    s_.leafIn.assign(tree.leaves.size(), 0);
  }

  bool nodeInside(uint32_t n) const {
    const CsgTree::Node &node = tree_.nodes[n];
    switch (node.op) {
    case CsgOp::Union:
    case CsgOp::Merge: return s_.count[n] > 0;
    case CsgOp::Intersection: return s_.count[n] == int32_t(node.children);
    case CsgOp::Difference: return s_.baseIn[n] && s_.count[n] == 0;
    }
    return false;
  }

  bool rootInside() const { return nodeInside(0); }

  /// Leaf `leaf` now inside (`in`) or not: updates the nodes above it.
  void set(uint32_t leaf, bool in) {
    if (bool(s_.leafIn[leaf]) == in) return;
    s_.leafIn[leaf] = in;
    const CsgTree::Leaf &l = tree_.leaves[leaf];
    bool first = l.first;
    for (uint32_t n = l.parent; n != CsgTree::kNoParent;) {
      const CsgTree::Node &node = tree_.nodes[n];
      bool old = nodeInside(n);
      if (node.op == CsgOp::Difference && first) s_.baseIn[n] = in;
      else s_.count[n] += in ? 1 : -1;
      bool now = nodeInside(n);
      if (now == old) return;
      in = now;
      first = node.first;
      n = node.parent;
    }
  }

  /// Whether a crossing of leaf `leaf` here is a surface of the result: each
  /// operator above it keeps it, given its other children's states.
  bool kept(uint32_t leaf) const {
    const CsgTree::Leaf &l = tree_.leaves[leaf];
    int32_t self = s_.leafIn[leaf];
    bool first = l.first;
    for (uint32_t n = l.parent; n != CsgTree::kNoParent;) {
      const CsgTree::Node &node = tree_.nodes[n];
      const int32_t others = s_.count[n] - (node.op == CsgOp::Difference && first ? 0 : self);
      switch (node.op) {
      case CsgOp::Union: break;
      case CsgOp::Merge:
        if (others > 0) return false;
        break;
      case CsgOp::Intersection:
        if (others != int32_t(node.children) - 1) return false;
        break;
      case CsgOp::Difference:
        if (first ? others > 0 : !s_.baseIn[n] || others > 0) return false;
        break;
      }
      self = nodeInside(n);
      first = node.first;
      n = node.parent;
    }
    return true;
  }

private:
  const CsgTree &tree_;
  Scratch &s_;
};

/// Crossings closer together than this (relative to the ray's scale) are
/// one event: coincident surfaces.
constexpr double kCoincident = 0x1p-32;

/// The result's first surface in (ray.tMin, ray.tMax): its crossing, or
/// null. `AnyHit` stops at the first one found (the same one).
const Crossing *firstSurface(const CsgTree &tree, const Ray &ray, Scratch &s) {
  std::vector<Crossing> &c = s.crossings;
  c.clear();
  const double scale = maxAbsComponent(ray.o) / maxAbsComponent(ray.d);
  // Crossings up to a coincidence window past tMax are kept, so a group
  // straddling tMax is judged whole (the answer must not depend on how far
  // a backend's query reaches); only a surface below tMax is reported.
  const double limit = ray.tMax + kCoincident * (std::fabs(ray.tMax) + scale);
  for (uint32_t i = 0; i < tree.leaves.size(); ++i) {
    const CsgTree::Leaf &leaf = tree.leaves[i];
    if (!lineMeetsBox(ray, leaf.bounds)) continue;
    Span spans[kMaxSpans];
    double shift = 0;
    int n = shapeSpans(leaf.entity, ray, spans, shift);
    for (int k = 0; k < n; ++k) {
      const Span &sp = spans[k];
      const double t0 = sp.t0 + shift, t1 = sp.t1 + shift;
      if (!(t0 < limit)) break; // this and later spans start beyond the query
      c.push_back({t0, sp.t0, i, sp.part0, true});
      if (t1 < limit) c.push_back({t1, sp.t1, i, sp.part1, false});
    }
  }
  if (c.empty()) return nullptr;
  if (c.size() <= 16) {
    for (size_t i = 1; i < c.size(); ++i)
      for (size_t j = i; j > 0 && before(c[j], c[j - 1]); --j) std::swap(c[j], c[j - 1]);
  } else {
    std::sort(c.begin(), c.end(), before);
  }
  Sweep sweep(tree, s);
  for (size_t i = 0; i < c.size();) {
    // The group of crossings coincident with c[i].
    const double reach = c[i].t + kCoincident * (std::fabs(c[i].t) + scale);
    size_t end = i + 1;
    while (end < c.size() && c[end].t <= reach) ++end;
    auto candidate = [&](const Crossing &x) {
      return x.part >= 0 && x.t > ray.tMin && x.t < ray.tMax;
    };
    if (end == i + 1) {
      const Crossing &x = c[i];
      if (candidate(x) && sweep.kept(x.leaf)) return &x;
      sweep.set(x.leaf, x.entering);
    } else {
      bool any = false;
      for (size_t k = i; k < end; ++k) any = any || candidate(c[k]);
      if (!any) {
        for (size_t k = i; k < end; ++k) sweep.set(c[k].leaf, c[k].entering);
      } else {
        // Kept before the others cross and after them.
        s.keptBefore.assign(end - i, 0);
        s.keptAfter.assign(end - i, 0);
        const bool rootBefore = sweep.rootInside();
        for (size_t k = i; k < end; ++k) s.keptBefore[k - i] = sweep.kept(c[k].leaf);
        for (size_t k = i; k < end; ++k) sweep.set(c[k].leaf, c[k].entering);
        for (size_t k = i; k < end; ++k) s.keptAfter[k - i] = sweep.kept(c[k].leaf);
        const bool changed = sweep.rootInside() != rootBefore;
        const Crossing *pick = nullptr;
        for (size_t k = i; k < end && !pick; ++k) {
          if (!candidate(c[k])) continue;
          bool b = s.keptBefore[k - i], a = s.keptAfter[k - i];
          if (changed ? (a || b) : (a && b)) pick = &c[k];
        }
        if (!pick && changed) {
          for (size_t k = i; k < end && !pick; ++k)
            if (candidate(c[k])) pick = &c[k];
        }
        if (pick) return pick;
      }
    }
    i = end;
  }
  return nullptr;
}

Scratch &scratch() {
  thread_local Scratch s;
  return s;
}

} // namespace

bool intersectCsg(const Csg &csg, uint32_t entityIndex, const Ray &ray, Hit &hit) {
  if (!csg.tree) return false;
  const CsgTree &tree = *csg.tree;
  Scratch &s = scratch();
  const Crossing *x = firstSurface(tree, ray, s);
  if (!x) return false;
  const CsgTree::Leaf &leaf = tree.leaves[x->leaf];
  if (!fillShapeHit(leaf.entity, entityIndex, ray, x->tObject, x->part, hit)) return false;
  hit.primitive = x->leaf;
  if (leaf.inverted) {
    hit.ng = -hit.ng;
    hit.ns = -hit.ns;
  }
  if (leaf.inheritsTexture)
    hit.pObject = affinePoint(leaf.textureMotion ? leaf.textureMotion->inverseMatrixAt(hit.time)
                                                 : leaf.textureSpace.inverseMatrix(),
                              hit.p);
  return true;
}

bool occludedCsg(const Csg &csg, const Ray &ray) {
  return csg.tree && firstSurface(*csg.tree, ray, scratch()) != nullptr;
}

} // namespace lray
