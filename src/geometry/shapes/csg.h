// Pipeline: geometry. Constructive solid geometry (lua/README.md, "CSG"):
// Union, Merge, Intersection and Difference of solids, nested. The shape
// holds its whole tree (geometry/csg_tree.h), whose leaves are solid
// entities placed in world space; geometry/csg_ray.cpp intersects it from
// the leaves' own span code, so both backends run the same CSG code.
#pragma once

#include <cstdint>
#include <memory>

namespace lray {

enum class CsgOp : uint8_t {
  Union,        ///< every child's surface, inner ones included (POV-Ray's union)
  Merge,        ///< the union's outer surface only
  Intersection, ///< what is inside every child
  Difference,   ///< the first child minus every later one
};

/// The Lua class name of an operator ("Union", ...).
const char *csgOpName(CsgOp op);

struct CsgTree;

struct Csg {
  static constexpr const char *kName = "CSG";
  static constexpr bool kSolid = true; ///< a CSG node of solids is one (shape_list.h)
  std::shared_ptr<const CsgTree> tree; ///< null: nothing to hit
};

} // namespace lray
