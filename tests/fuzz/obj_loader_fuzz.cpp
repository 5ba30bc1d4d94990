// Fuzz target (libFuzzer): the native OBJ reader and the mesh builder
// behind mesh_from_obj (src/scene/obj_loader.h, mesh_builder.h). Any input
// must either give a valid MeshData or a SceneError; a crash, a sanitizer
// report, another exception or an invariant failure below is a bug.
#include "scene/mesh_builder.h"
#include "scene/obj_loader.h"
#include "util/scene_error.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace {

bool finite(const lray::Vec3f &v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check(bool ok) {
  if (!ok) std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string text(reinterpret_cast<const char *>(data), size);
  try {
    lray::MeshSource src = lray::parseObj(text, "fuzz.obj");
    lray::MeshDataPtr mesh = lray::buildMeshData(src);
    // What the backends rely on: every index in range, positions finite
    // (a non-finite vertex must be an error, not data), the flat index
    // list matching the triangles.
    check(mesh->triangleIndices.size() == 3 * mesh->triangles.size());
    for (const lray::Vec3f &p : mesh->positions) check(finite(p));
    for (size_t i = 0; i < mesh->triangles.size(); ++i) {
      const lray::MeshTriangle &t = mesh->triangles[i];
      for (int k = 0; k < 3; ++k) {
        check(t.v[k] < mesh->positions.size());
        check(mesh->triangleIndices[3 * i + k] == t.v[k]);
        check(t.uv[k] < static_cast<int32_t>(mesh->uvs.size()));
        check(t.n[k] < static_cast<int32_t>(mesh->normals.size()));
      }
    }
  } catch (const lray::SceneError &) {
    // A clear user error: fine.
  }
  return 0;
}
