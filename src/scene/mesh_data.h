// Pipeline: scene description. Triangle mesh data, shared (not copied) by
// every Mesh that was made with copy(): the renderer turns the sharers into
// instances of one geometry.
#pragma once

#include "math/vec3.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace lray {

/// One triangle's corner indices (0-based). uv/normal index -1 = absent.
struct MeshTriangle {
  uint32_t v[3];
  int32_t uv[3] = {-1, -1, -1};
  int32_t n[3] = {-1, -1, -1};
};

/// Immutable mesh geometry in the mesh's object space. Vertex positions are
/// float because Embree reads the same buffer (no second copy).
/// `normals` is always filled by the scene layer (given, or area-weighted
/// vertex normals when missing); `triangleIndices` is the flat v0 v1 v2 list
/// Embree and the kd-tree read.
struct MeshData {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;
  std::vector<Vec2f> uvs;
  std::vector<MeshTriangle> triangles;
  /// Flat 3*N vertex indices, same order as `triangles`.
  std::vector<uint32_t> triangleIndices;
  /// True when the user supplied uvs for every corner (else the default
  /// per-triangle (0,0),(1,0),(0,1) mapping applies).
  bool hasUvs = false;
  /// True when normal indices are present for every corner.
  bool hasNormals = false;
  /// B >= 0 when every corner's normal index is its vertex index + B and no
  /// corner has a uv index (the scene layer's computed vertex normals):
  /// the hit code then needs only the 12-byte `triangleIndices` entry of a
  /// triangle, not its 36-byte MeshTriangle. -1 otherwise. Set by
  /// updateVertexNormalBase() once `triangles` is complete.
  int32_t vertexNormalBase = -1;

  void updateVertexNormalBase() {
    vertexNormalBase = -1;
    if (triangles.empty()) return;
    int64_t base = int64_t(triangles[0].n[0]) - triangles[0].v[0];
    if (base < 0) return;
    for (const MeshTriangle &t : triangles)
      for (int k = 0; k < 3; ++k)
        if (t.uv[k] >= 0 || int64_t(t.n[k]) - t.v[k] != base) return;
    vertexNormalBase = static_cast<int32_t>(base);
  }

  size_t memoryBytes() const {
    return positions.capacity() * sizeof(Vec3f) + normals.capacity() * sizeof(Vec3f) +
           uvs.capacity() * sizeof(Vec2f) + triangles.capacity() * sizeof(MeshTriangle) +
           triangleIndices.capacity() * sizeof(uint32_t);
  }
};

using MeshDataPtr = std::shared_ptr<const MeshData>;

} // namespace lray
