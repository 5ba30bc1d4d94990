// Pipeline: geometry. See csg_tree.h.
#include "geometry/csg_tree.h"

#include "geometry/shape.h"

#include <algorithm>
#include <cassert>

namespace lray {

const char *csgOpName(CsgOp op) {
  switch (op) {
  case CsgOp::Union: return "Union";
  case CsgOp::Merge: return "Merge";
  case CsgOp::Intersection: return "Intersection";
  case CsgOp::Difference: return "Difference";
  }
  return "CSG";
}

namespace {

/// Whether a child added now under `parent` is subtracted by it.
bool subtractedBy(const CsgTree::Node &parent) {
  return parent.op == CsgOp::Difference && parent.children > 0;
}

} // namespace

uint32_t CsgTree::addNode(CsgOp op, uint32_t parent) {
  assert((parent == kNoParent) == nodes.empty());
  Node n;
  n.op = op;
  n.parent = parent;
  if (parent != kNoParent) {
    Node &p = nodes[parent];
    n.first = p.children == 0;
    n.inverted = p.inverted != subtractedBy(p);
    ++p.children;
  }
  nodes.push_back(n);
  return static_cast<uint32_t>(nodes.size() - 1);
}

uint32_t CsgTree::addLeaf(Entity entity, uint32_t parent) {
  assert(parent < nodes.size());
  Node &p = nodes[parent];
  Leaf l;
  l.parent = parent;
  l.first = p.children == 0;
  l.inverted = p.inverted != subtractedBy(p);
  ++p.children;
  l.bounds = shapeWorldBounds(entity);
  l.entity = std::move(entity);
  leaves.push_back(std::move(l));
  return static_cast<uint32_t>(leaves.size() - 1);
}

void CsgTree::finish() {
  // Children come after their parents: combine bottom-up, last node first.
  std::vector<bool> seen(nodes.size(), false);
  auto combine = [&](uint32_t parent, const Bounds3 &box, bool first) {
    const Bounds3 child = box.empty() ? Bounds3() : box; // canonical: extend() ignores it
    Node &p = nodes[parent];
    if (!seen[parent]) {
      p.bounds = child;
      seen[parent] = true;
      return;
    }
    switch (p.op) {
    case CsgOp::Union:
    case CsgOp::Merge: p.bounds.extend(child); break;
    case CsgOp::Intersection:
      p.bounds.lo = max(p.bounds.lo, child.lo);
      p.bounds.hi = min(p.bounds.hi, child.hi);
      break;
    case CsgOp::Difference:
      if (first) p.bounds = child;
      break;
    }
  };
  // A Difference's bounds are its first child's: visit children in order
  // (leaves and nodes interleave, so the first child is found by its flag).
  for (const Leaf &l : leaves) combine(l.parent, l.bounds, l.first);
  for (uint32_t i = static_cast<uint32_t>(nodes.size()); i-- > 1;)
    combine(nodes[i].parent, nodes[i].bounds, nodes[i].first);
  bounds = nodes.front().bounds;
  if (bounds.empty()) bounds = Bounds3(); // canonical empty box
  maxDepth = 0;
  for (const Leaf &l : leaves) {
    uint32_t depth = 1;
    for (uint32_t n = l.parent; n != kNoParent; n = nodes[n].parent) ++depth;
    maxDepth = std::max(maxDepth, depth);
  }
}

} // namespace lray
