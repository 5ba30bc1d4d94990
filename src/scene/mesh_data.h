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

  size_t memoryBytes() const {
    return positions.capacity() * sizeof(Vec3f) + normals.capacity() * sizeof(Vec3f) +
           uvs.capacity() * sizeof(Vec2f) + triangles.capacity() * sizeof(MeshTriangle) +
           triangleIndices.capacity() * sizeof(uint32_t);
  }
};

using MeshDataPtr = std::shared_ptr<const MeshData>;

} // namespace lray
