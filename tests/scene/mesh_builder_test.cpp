// MeshSource -> MeshData: fanning, normals, uvs, index validation.
#include "scene/mesh_builder.h"
#include "util/scene_error.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

MeshSource quad() {
  MeshSource s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  for (int32_t i : {0, 3, 2, 1}) s.corners.push_back({i, -1, -1});
  s.faceSizes = {4};
  return s;
}

TEST(MeshBuilderTest, FansPolygonsFromTheFirstCorner) {
  MeshDataPtr m = buildMeshData(quad());
  ASSERT_EQ(m->triangles.size(), 2u);
  EXPECT_EQ(m->triangleIndices, (std::vector<uint32_t>{0, 3, 2, 0, 2, 1}));
  EXPECT_EQ(m->positions.size(), 4u);
}

TEST(MeshBuilderTest, ComputesVertexNormalsWhenAbsent) {
  MeshDataPtr m = buildMeshData(quad());
  EXPECT_FALSE(m->hasNormals);
  EXPECT_FALSE(m->hasUvs);
  ASSERT_EQ(m->normals.size(), 4u);
  for (const MeshTriangle &t : m->triangles)
    for (int j = 0; j < 3; ++j) {
      ASSERT_GE(t.n[j], 0);
      EXPECT_EQ(t.n[j], static_cast<int32_t>(t.v[j]));
      EXPECT_NEAR(m->normals[t.n[j]].y, 1, 1e-6); // (0,0,1)x(1,0,1) winding faces +y
    }
}

TEST(MeshBuilderTest, NormalsAreAreaWeighted) {
  // Two triangles share vertex 0: a big one facing +z and a small one facing -x.
  MeshSource s;
  s.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 1, 0}, {0, 0, -1}};
  for (int32_t i : {0, 1, 2, 0, 3, 4}) s.corners.push_back({i, -1, -1});
  s.faceSizes = {3, 3};
  MeshDataPtr m = buildMeshData(s);
  Vec3f n = m->normals[0];
  // Areas 8 and 0.5: the normal leans 16:1 towards +z.
  EXPECT_NEAR(n.z / n.x, -16, 1e-4);
}

TEST(MeshBuilderTest, ComputedNormalsLetTheHitCodeSkipMeshTriangles) {
  EXPECT_EQ(buildMeshData(quad())->vertexNormalBase, 0);
}

TEST(MeshBuilderTest, KeepsGivenNormalsAndUvs) {
  MeshSource s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.normals = {{0, 0, -1}};
  s.uvs = {{0, 0}, {1, 0}, {0, 1}};
  for (int32_t i : {0, 1, 2}) s.corners.push_back({i, i, 0});
  s.faceSizes = {3};
  MeshDataPtr m = buildMeshData(s);
  EXPECT_TRUE(m->hasNormals);
  EXPECT_TRUE(m->hasUvs);
  EXPECT_EQ(m->normals.size(), 1u);
  EXPECT_EQ(m->triangles[0].n[2], 0);
  EXPECT_EQ(m->triangles[0].uv[1], 1);
  EXPECT_EQ(m->vertexNormalBase, -1); // uv indices need the MeshTriangle
}

TEST(MeshBuilderTest, CornersWithoutNormalsGetComputedOnesAfterTheGivenOnes) {
  MeshSource s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.normals = {{0, 0, -1}};
  s.corners = {{0, -1, 0}, {1, -1, -1}, {2, -1, 0}};
  s.faceSizes = {3};
  MeshDataPtr m = buildMeshData(s);
  EXPECT_FALSE(m->hasNormals);
  ASSERT_EQ(m->normals.size(), 4u);
  EXPECT_EQ(m->triangles[0].n[0], 0);
  EXPECT_EQ(m->triangles[0].n[1], 2); // 1 given + vertex 1
}

TEST(MeshBuilderTest, OutOfRangeIndicesNameTheFaceAndCorner) {
  MeshSource s = quad();
  s.corners[2].v = 9;
  try {
    buildMeshData(s);
    FAIL();
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(), "face 1, corner 3: vertex index 10 is out of range (4 vertices)");
  }
  s = quad();
  s.corners[1].n = 0;
  try {
    buildMeshData(s);
    FAIL();
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(), "face 1, corner 2: normal index 1 is out of range (0 normals)");
  }
}

} // namespace
} // namespace lray
