// Pipeline: acceleration (kd-tree backend). The compact 8-byte node of the
// kd-tree (pbrt style): one word holds the split position or the leaf's
// primitive list offset, the other the axis/leaf flag and a count or child index.
#pragma once

#include <cstdint>

namespace lray {

/// One kd-tree node. Interior nodes keep their two children next to each
/// other in the node array (below child at `childIndex()`, above child right
/// after it); leaves store the offset of their list in the tree's
/// primitive-index array, so per-reference data kept in that order (a mesh
/// tree's triangle corners) is addressed the same way.
class KdNode {
public:
  /// Interior node splitting at `split` along `axis` (0..2), children at
  /// belowChild and belowChild + 1.
  static KdNode interior(int axis, float split, uint32_t belowChild) {
    KdNode n;
    n.split_ = split;
    n.bits_ = (belowChild << 2) | static_cast<uint32_t>(axis);
    return n;
  }
  /// Leaf of nPrims primitives listed from `offset` in the tree's index array.
  static KdNode leaf(uint32_t nPrims, uint32_t offset) {
    KdNode n;
    n.prims_ = offset;
    n.bits_ = (nPrims << 2) | 3u;
    return n;
  }

  /// True for leaves (flag value 3 in the axis bits).
  bool isLeaf() const { return (bits_ & 3u) == 3u; }
  /// True for leaves without primitives.
  bool isEmptyLeaf() const { return bits_ == 3u; }
  /// Split axis (0 = x, 1 = y, 2 = z) of an interior node.
  int axis() const { return static_cast<int>(bits_ & 3u); }
  /// Split plane position along axis(), in the tree's space (world or mesh object space).
  float split() const { return split_; }
  /// Index of the below child; the above child is the next node.
  uint32_t childIndex() const { return bits_ >> 2; }
  /// Number of primitives of a leaf.
  uint32_t primCount() const { return bits_ >> 2; }
  /// Offset of the leaf's list in the tree's primitive-index array.
  uint32_t primOffset() const { return prims_; }

  /// Nodes and leaf counts are limited to 2^30 by the 2 flag bits.
  static constexpr uint32_t kMaxIndex = (1u << 30) - 1;

private:
  union {
    float split_;
    uint32_t prims_;
  };
  uint32_t bits_ = 0;
};

static_assert(sizeof(KdNode) == 8, "KdNode must stay 8 bytes");

} // namespace lray
