// Pipeline: scene description. MeshSource -> MeshData (see mesh_builder.h).
#include "scene/mesh_builder.h"

#include "util/scene_error.h"

#include <cmath>
#include <string>

namespace lray {

namespace {

void checkIndex(int32_t index, size_t count, bool optional, size_t face, uint32_t corner,
                const char *what, const char *plural) {
  if (optional && index == -1) return;
  if (index < 0 || static_cast<size_t>(index) >= count) {
    throw SceneError("face " + std::to_string(face + 1) + ", corner " + std::to_string(corner + 1) +
                     ": " + what + " index " + std::to_string(int64_t(index) + 1) +
                     " is out of range (" + std::to_string(count) + " " + plural + ")");
  }
}

} // namespace

MeshDataPtr buildMeshData(const MeshSource &src) {
  auto data = std::make_shared<MeshData>();
  data->positions = src.positions;
  data->uvs = src.uvs;
  data->normals = src.normals;

  size_t triangleCount = 0;
  for (uint32_t size : src.faceSizes) triangleCount += size >= 3 ? size - 2 : 0;
  data->triangles.reserve(triangleCount);

  bool allUvs = !src.uvs.empty();
  bool allNormals = !src.normals.empty();
  size_t first = 0;
  for (size_t face = 0; face < src.faceSizes.size(); ++face) {
    uint32_t size = src.faceSizes[face];
    if (size < 3)
      throw SceneError("face " + std::to_string(face + 1) + ": has " + std::to_string(size) +
                       " corners, needs at least 3");
    if (first + size > src.corners.size())
      throw SceneError("face " + std::to_string(face + 1) + ": corner list is truncated");
    for (uint32_t c = 0; c < size; ++c) {
      const MeshCorner &k = src.corners[first + c];
      checkIndex(k.v, src.positions.size(), false, face, c, "vertex", "vertices");
      checkIndex(k.uv, src.uvs.size(), true, face, c, "uv", "uvs");
      checkIndex(k.n, src.normals.size(), true, face, c, "normal", "normals");
      allUvs = allUvs && k.uv >= 0;
      allNormals = allNormals && k.n >= 0;
    }
    // Fan from the first corner: (0, i, i+1).
    for (uint32_t i = 1; i + 1 < size; ++i) {
      MeshTriangle t;
      const MeshCorner *cs[3] = {&src.corners[first], &src.corners[first + i],
                                 &src.corners[first + i + 1]};
      for (int j = 0; j < 3; ++j) {
        t.v[j] = static_cast<uint32_t>(cs[j]->v);
        t.uv[j] = cs[j]->uv;
        t.n[j] = cs[j]->n;
      }
      data->triangles.push_back(t);
    }
    first += size;
  }
  data->hasUvs = allUvs && !data->triangles.empty();
  data->hasNormals = allNormals && !data->triangles.empty();

  if (!data->hasNormals) {
    // Area-weighted vertex normals: the unnormalised cross product of two
    // edges is twice the triangle's area along its normal.
    std::vector<Vec3> sums(src.positions.size());
    for (const MeshTriangle &t : data->triangles) {
      Vec3 p0 = toVec3(src.positions[t.v[0]]), p1 = toVec3(src.positions[t.v[1]]),
           p2 = toVec3(src.positions[t.v[2]]);
      Vec3 n = cross(p1 - p0, p2 - p0);
      for (int j = 0; j < 3; ++j) sums[t.v[j]] += n;
    }
    const auto base = static_cast<int32_t>(data->normals.size());
    data->normals.reserve(data->normals.size() + sums.size());
    for (const Vec3 &s : sums) {
      double len = length(s);
      // A vertex used only by degenerate triangles has no defined normal.
      Vec3 n = len > 0 && std::isfinite(len) ? s / len : Vec3(0, 1, 0);
      data->normals.push_back({float(n.x), float(n.y), float(n.z)});
    }
    for (MeshTriangle &t : data->triangles)
      for (int j = 0; j < 3; ++j)
        if (t.n[j] < 0) t.n[j] = base + static_cast<int32_t>(t.v[j]);
  }

  data->triangleIndices.reserve(data->triangles.size() * 3);
  for (const MeshTriangle &t : data->triangles)
    data->triangleIndices.insert(data->triangleIndices.end(), t.v, t.v + 3);
  data->updateVertexNormalBase();
  return data;
}

} // namespace lray
