// Pipeline: geometry. A CSG entity's tree, flattened for the ray code
// (csg_ray.h): operator nodes and solid leaves in arrays, each knowing its
// parent. Built once per frame by the scene converter (or a test) with
// addNode/addLeaf, parents before children, then finish().
#pragma once

#include "math/bounds.h"
#include "math/transform_motion.h"
#include "geometry/shapes/csg.h"
#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace lray {

struct CsgTree {
  static constexpr uint32_t kNoParent = ~0u;

  struct Node {
    CsgOp op;
    uint32_t parent = kNoParent; ///< kNoParent for the root (node 0)
    uint32_t children = 0;
    bool first = false;    ///< the first child of its parent (a Difference's base)
    bool inverted = false; ///< subtracted an odd number of times on the way to the root
    Bounds3 bounds;        ///< world; set by finish()
  };

  struct Leaf {
    Entity entity; ///< a solid analytic shape in world space, with its texture
    uint32_t parent = kNoParent;
    bool first = false;
    /// Its surface faces out of a subtracted solid: the result's normal is
    /// the shape's reversed (a Difference's carved surface faces the hole).
    bool inverted = false;
    Bounds3 bounds; ///< world, padded; infinite for a Plane
    /// The texture came from an enclosing CSG node (POV-Ray's rule): its
    /// pigment is evaluated in that node's space, `textureSpace` (world from
    /// node), not in the leaf's own.
    bool inheritsTexture = false;
    Transform textureSpace;
    /// textureSpace over the shutter where the node's placement moves
    /// (lua/README.md, "Motion blur"): read at the hit's time.
    std::shared_ptr<const TransformMotion> textureMotion;
  };

  std::vector<Node> nodes;   ///< [0] = root
  std::vector<Leaf> leaves;
  Bounds3 bounds;            ///< of the result (tight as the operators allow)
  uint32_t maxDepth = 0;     ///< nodes from the root to the deepest leaf

  /// Adds an operator node under `parent` (kNoParent: the root, first call only).
  uint32_t addNode(CsgOp op, uint32_t parent);
  /// Adds a solid leaf under node `parent`.
  uint32_t addLeaf(Entity entity, uint32_t parent);
  /// Computes the bounds: a Union's or Merge's is the union of its
  /// children's, an Intersection's their intersection, a Difference's its
  /// first child's. Every node must have a child.
  void finish();

  CsgOp rootOp() const { return nodes.front().op; }
};

} // namespace lray
