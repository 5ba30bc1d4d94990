// Pipeline: geometry. Mesh (lua/README.md, "Entities"): a triangle mesh. Its geometry is
// Entity::mesh (shared between copies) and its triangles are intersected by
// each backend's own triangle test, then filled by the shared triangle code
// (geometry/shape.h fillTriangleHit); this tag only puts it in the shape list.
#pragma once

namespace lray {

struct Mesh {
  static constexpr const char *kName = "Mesh";
  /// Its triangles need not close: no inside, so CSG does not take it.
  static constexpr bool kSolid = false;
};

} // namespace lray
