// Test helper: a square (or any quadrilateral) as a mesh entity of two
// triangles, for scenes the shading tests build by hand.
#pragma once

#include "scene/scene.h"

#include <array>
#include <memory>

namespace lray::testing {

/// Adds a mesh entity of triangles (0, 1, 2) and (0, 2, 3) over `corners`
/// (its face normal by the right-hand rule on that order), with `texture`,
/// placed by `placement`.
inline void addQuad(Scene &scene, const std::array<Vec3f, 4> &corners, uint32_t texture,
                    const Transform &placement = Transform()) {
  auto mesh = std::make_shared<MeshData>();
  mesh->positions.assign(corners.begin(), corners.end());
  mesh->triangles = {MeshTriangle{{0, 1, 2}}, MeshTriangle{{0, 2, 3}}};
  for (const MeshTriangle &t : mesh->triangles)
    mesh->triangleIndices.insert(mesh->triangleIndices.end(), t.v, t.v + 3);
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = mesh;
  e.worldFromObject = placement;
  e.texture = texture;
  scene.entities.push_back(e);
}

} // namespace lray::testing
