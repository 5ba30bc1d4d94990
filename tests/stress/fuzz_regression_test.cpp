// Robustness suite (issue 8): inputs found by the libFuzzer targets in
// tests/fuzz/ (bench/fuzz), kept as regression tests.
#include "scene/mesh_builder.h"
#include "scene/obj_loader.h"
#include "util/scene_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace lray {
namespace {

/// The OBJ must load into finite data or be rejected with a SceneError.
void expectFiniteOrSceneError(const std::string &text) {
  try {
    MeshDataPtr mesh = buildMeshData(parseObj(text, "fuzz.obj"));
    for (const Vec3f &p : mesh->positions)
      EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
          << "a vertex became non-finite without an error";
    for (const Vec3f &n : mesh->normals)
      EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    for (const Vec2f &t : mesh->uvs) EXPECT_TRUE(std::isfinite(t.u) && std::isfinite(t.v));
  } catch (const SceneError &e) {
    EXPECT_NE(std::string(e.what()).find("fuzz.obj:"), std::string::npos) << e.what();
  }
}

// obj_loader_fuzz crash-ad05a98f (and 17 more like it): a coordinate finite
// as a double (5.6e43) but beyond single precision became +Inf in
// MeshData::positions.
TEST(StressFuzzRegression, ObjCoordinateBeyondFloatRange) {
  expectFiniteOrSceneError("v 0 0555555555555555555555555555555555555555555 0\nv 1 0 0\nv 0 1 0\n"
                           "vt 0 0\nvt 1 0\nf 1 2 3\n");
  expectFiniteOrSceneError("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1e39\nf 1//1 2//1 3//1\n");
  expectFiniteOrSceneError("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 -1e39\nf 1/1 2/1 3/1\n");
}

// The same values in range load.
TEST(StressFuzzRegression, ObjCoordinateAtFloatRangeLoads) {
  MeshDataPtr mesh = buildMeshData(parseObj("v 0 3e38 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "fuzz.obj"));
  ASSERT_EQ(mesh->positions.size(), 3u);
  EXPECT_TRUE(std::isfinite(mesh->positions[0].y));
}

} // namespace
} // namespace lray
