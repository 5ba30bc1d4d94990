// Pipeline: geometry (internal). Prefetches for a batch of mesh hits before
// fillTriangleHit (triangle_hit.cpp) reads them: a backend that has several
// hits at once (Embree's packets) starts all their cache misses first.
#pragma once

#include "scene/mesh_data.h"

#include <cstddef>
#include <cstdint>

namespace lray {

/// Stage 1: the triangle's corner record, the one fillTriangleHit reads.
inline void prefetchTriangleCorners(const MeshData &mesh, uint32_t triangle) {
  if (mesh.vertexNormalBase >= 0)
    __builtin_prefetch(&mesh.triangleIndices[3 * size_t(triangle)]);
  else
    __builtin_prefetch(&mesh.triangles[triangle]);
}

/// Stage 2 (once stage 1 was issued for the whole batch): the corners'
/// positions and normals.
inline void prefetchTriangleVertices(const MeshData &mesh, uint32_t triangle) {
  if (mesh.vertexNormalBase >= 0) {
    const uint32_t *v = &mesh.triangleIndices[3 * size_t(triangle)];
    for (int k = 0; k < 3; ++k) {
      __builtin_prefetch(&mesh.positions[v[k]]);
      __builtin_prefetch(&mesh.normals[v[k] + uint32_t(mesh.vertexNormalBase)]);
    }
    return;
  }
  const MeshTriangle &t = mesh.triangles[triangle];
  for (int k = 0; k < 3; ++k) {
    __builtin_prefetch(&mesh.positions[t.v[k]]);
    if (t.n[k] >= 0) __builtin_prefetch(&mesh.normals[t.n[k]]);
  }
}

} // namespace lray
