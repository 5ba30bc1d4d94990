// Pipeline: scene description. Turns a mesh as written by the user (faces of
// any size, optional uvs and normals) into the immutable triangle MeshData
// the backends read: validates indices, fans polygons, fills normals.
#pragma once

#include "scene/mesh_data.h"

#include <cstdint>
#include <vector>

namespace lray {

/// One face corner, 0-based indices into MeshSource arrays; -1 = absent.
struct MeshCorner {
  int32_t v = -1;
  int32_t uv = -1;
  int32_t n = -1;
};

/// A mesh as the user described it (Lua tables or an OBJ file), object space.
struct MeshSource {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;
  std::vector<Vec2f> uvs;
  std::vector<MeshCorner> corners; ///< all faces' corners, face after face
  std::vector<uint32_t> faceSizes; ///< corners per face (>= 3)
};

/// Builds the triangle data: faces with more than three corners are fanned
/// from their first corner; corners without a normal get the area-weighted
/// vertex normal (appended after the given normals), so every triangle
/// corner has a valid normal index. Throws SceneError("face N: ...", no
/// location; 1-based face and corner numbers) for an index out of range.
MeshDataPtr buildMeshData(const MeshSource &source);

} // namespace lray
