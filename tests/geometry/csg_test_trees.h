// Test helpers: CSG trees written as nested descriptions, built into a CSG
// entity as the scene converter builds them (transforms composed down the
// tree, leaves in world space), and an independent point-membership test
// of every solid for oracles.
#pragma once

#include "geometry/csg_tree.h"
#include "geometry/shape.h"
#include "scene/scene.h"

#include <memory>
#include <optional>
#include <vector>

namespace lray::test {

/// One node as written: an operator over children, or a solid leaf.
struct CsgSpec {
  std::optional<CsgOp> op;       ///< none: a leaf
  std::vector<CsgSpec> children; ///< operators only
  Entity leaf;                   ///< leaves only (object placement relative to the parent)
  Transform transform;           ///< operators: on top of the children's
};

inline CsgSpec leafSpec(ShapeKind kind, const Transform &xf) {
  CsgSpec s;
  s.leaf.shape = makeShape(kind);
  s.leaf.worldFromObject = xf;
  return s;
}

inline CsgSpec opSpec(CsgOp op, std::vector<CsgSpec> children, const Transform &xf = {}) {
  CsgSpec s;
  s.op = op;
  s.children = std::move(children);
  s.transform = xf;
  return s;
}

inline void addSpec(CsgTree &tree, const CsgSpec &spec, uint32_t parent, const Transform &world) {
  if (!spec.op) {
    Entity e = spec.leaf;
    e.worldFromObject = world * spec.leaf.worldFromObject;
    tree.addLeaf(std::move(e), parent);
    return;
  }
  const Transform here = world * spec.transform;
  uint32_t node = tree.addNode(*spec.op, parent);
  for (const CsgSpec &c : spec.children) addSpec(tree, c, node, here);
}

/// A CSG entity of the operator tree `spec`.
inline Entity csgEntity(const CsgSpec &spec) {
  auto tree = std::make_shared<CsgTree>();
  addSpec(*tree, spec, CsgTree::kNoParent, Transform());
  tree->finish();
  Entity e;
  e.shape = Csg{tree};
  e.worldFromObject = spec.transform;
  return e;
}

/// Whether the world point p is inside the solid entity e (boundary
/// included), from its definition in object space: no ray code involved.
inline bool insideSolid(const Entity &e, const Vec3 &world) {
  const auto &m = e.worldFromObject.inverseMatrix().m;
  const Vec3 p(m[0][0] * world.x + m[0][1] * world.y + m[0][2] * world.z + m[0][3],
               m[1][0] * world.x + m[1][1] * world.y + m[1][2] * world.z + m[1][3],
               m[2][0] * world.x + m[2][1] * world.y + m[2][2] * world.z + m[2][3]);
  switch (e.kind()) {
  case ShapeKind::Sphere: return dot(p, p) <= 1;
  case ShapeKind::Cube:
    return std::fabs(p.x) <= 0.5 && std::fabs(p.y) <= 0.5 && std::fabs(p.z) <= 0.5;
  case ShapeKind::Cylinder: return p.x * p.x + p.z * p.z <= 1 && p.y >= 0 && p.y <= 1;
  case ShapeKind::Cone:
    return p.y >= 0 && p.y <= 1 && p.x * p.x + p.z * p.z <= (1 - p.y) * (1 - p.y);
  case ShapeKind::Torus: {
    const Torus &t = std::get<Torus>(e.shape);
    double rho = std::sqrt(p.x * p.x + p.z * p.z) - t.major;
    return rho * rho + p.y * p.y <= t.minor * t.minor;
  }
  case ShapeKind::Plane: return p.y <= 0;
  default: return false;
  }
}

} // namespace lray::test
