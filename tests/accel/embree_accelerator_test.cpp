// Tests for src/accel/embree: EmbreeAccelerator over hand-built scenes,
// against the shared shape code and a brute-force double reference.
#include "accel/embree/embree_accelerator.h"

#include "accel_test_scenes.h"
#include "hit_expect.h"
#include "geometry/shape.h"

#include <gtest/gtest.h>

#include <random>

namespace lray {
namespace {

using testing::bruteForce;
using testing::expectSameHit;
using testing::makeJitteredSphere;
using testing::makeMesh;
using testing::meshEntity;
using testing::shapeEntity;

Scene mixedScene() {
  Scene s;
  auto quad = makeMesh({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, {0, 2, 1, 0, 3, 2});
  s.entities.push_back(shapeEntity(ShapeKind::Sphere, Transform::translate({0, 1, 5})));
  s.entities.push_back(meshEntity(quad, Transform::translate({0, -1, 5}) *
                                            Transform::scale(10, 1, 10)));
  s.entities.push_back(shapeEntity(ShapeKind::Cube, Transform::translate({3, 0, 6}) *
                                                        Transform::rotate({1, 1, 0}, 30)));
  s.entities.push_back(shapeEntity(ShapeKind::Cylinder, Transform::translate({-3, -1, 6})));
  s.entities.push_back(shapeEntity(ShapeKind::Cone, Transform::translate({-3, 0.5, 3}) *
                                                        Transform::scale(0.5, 1, 0.5)));
  // A copy of the quad, tilted: shares the MeshData.
  s.entities.push_back(meshEntity(quad, Transform::translate({2, 2, 8}) *
                                            Transform::rotate({1, 0, 0}, -60)));
  s.textures.push_back({});
  return s;
}

TEST(EmbreeAccelerator, EmptySceneHasNoHits) {
  Scene s;
  EmbreeAccelerator accel(s);
  Hit h;
  EXPECT_FALSE(accel.intersect({{0, 0, 0}, {0, 0, 1}}, h));
  EXPECT_FALSE(accel.occluded({{0, 0, 0}, {0, 0, 1}}));
  Ray rays[3] = {{{0, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {0, 1, 0}}};
  Hit hits[3];
  uint8_t found[3] = {7, 7, 7}, occl[3] = {7, 7, 7};
  accel.intersectCoherent(rays, 3, hits, found);
  accel.occludedCoherent(rays, 3, occl, nullptr);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(found[i], 0);
    EXPECT_EQ(occl[i], 0);
  }
  EXPECT_EQ(accel.stats().primitives, 0u);
  EXPECT_EQ(accel.stats().instances, 0u);
}

TEST(EmbreeAccelerator, AnalyticHitIsTheShapeCodesHit) {
  Scene s;
  s.entities.push_back(shapeEntity(ShapeKind::Sphere, Transform::translate({0.1, 0.2, 5}) *
                                                          Transform::scale(1, 2, 0.5)));
  EmbreeAccelerator accel(s);
  Ray ray{{0.013, 0.4, -1.7}, {0.01, 0.02, 1}};
  Hit viaEmbree, direct;
  ASSERT_TRUE(accel.intersect(ray, viaEmbree));
  ASSERT_TRUE(intersectShape(s.entities[0], 0, ray, direct));
  expectSameHit(viaEmbree, direct);
  // The double interval is honoured, not the float one Embree sees.
  Ray shortRay = ray;
  shortRay.tMax = std::nextafter(direct.t, 0.0);
  EXPECT_FALSE(accel.intersect(shortRay, viaEmbree));
  EXPECT_FALSE(accel.occluded(shortRay));
  shortRay.tMax = std::nextafter(direct.t, 1e300);
  EXPECT_TRUE(accel.occluded(shortRay));
}

TEST(EmbreeAccelerator, MatchesBruteForceOnMixedScene) {
  Scene s = mixedScene();
  EmbreeAccelerator accel(s);
  AcceleratorStats st = accel.stats();
  // 4 analytic + the quad's 2 triangles placed twice in the world (a mesh
  // that few entities share is not instanced).
  EXPECT_EQ(st.primitives, 4u + 2u * 2u);
  EXPECT_EQ(st.instances, 0u);
  EXPECT_GT(st.memoryBytes, 0u);
  EXPECT_GE(st.buildSeconds, 0);

  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 4000;
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    Vec3 o{u(rng) * 0.5, u(rng) * 0.5, -2};
    Vec3 target{u(rng) * 6, u(rng) * 4, 6 + u(rng) * 3};
    rays.push_back({o, target - o});
  }
  std::vector<Hit> hits(n);
  std::vector<uint8_t> found(n), occl(n);
  accel.intersectCoherent(rays.data(), n, hits.data(), found.data());
  accel.occludedCoherent(rays.data(), n, occl.data(), nullptr);
  int hitCount = 0, meshHits = 0;
  for (int i = 0; i < n; ++i) {
    auto [entity, t] = bruteForce(s, rays[i]);
    Hit h;
    bool hit = accel.intersect(rays[i], h);
    ASSERT_EQ(hit, entity >= 0) << i;
    ASSERT_EQ(found[i], hit ? 1 : 0) << i;
    ASSERT_EQ(occl[i], hit ? 1 : 0) << i;
    ASSERT_EQ(accel.occluded(rays[i]), hit) << i;
    if (!hit) continue;
    ++hitCount;
    ASSERT_EQ(h.entity, static_cast<uint32_t>(entity)) << i;
    ASSERT_NEAR(h.t, t, 1e-5 * t) << i;
    expectSameHit(hits[i], h);
    if (s.entities[entity].kind() == ShapeKind::Mesh) {
      ++meshHits;
      // Instance: the object point is in the shared mesh's own space.
      Vec3 back = s.entities[entity].worldFromObject.applyPoint(h.pObject);
      EXPECT_LT(length(back - h.p), 1e-9);
      EXPECT_NEAR(h.pObject.y, 0, 1e-6);
    }
  }
  EXPECT_GT(hitCount, n / 3);
  EXPECT_GT(meshHits, n / 20);
}

TEST(EmbreeAccelerator, TriangleHitFields) {
  // One triangle in the plane z = 2 with uvs and per-corner normals.
  auto mesh = makeMesh({{0, 0, 2}, {1, 0, 2}, {0, 1, 2}}, {0, 1, 2});
  mesh->uvs = {{0.5f, 0.5f}, {1.5f, 0.5f}, {0.5f, 2.5f}};
  mesh->normals = {{0, 0, -1}, {0, 0.6f, -0.8f}, {0.6f, 0, -0.8f}};
  mesh->triangles[0].uv[0] = 0, mesh->triangles[0].uv[1] = 1, mesh->triangles[0].uv[2] = 2;
  mesh->triangles[0].n[0] = 0, mesh->triangles[0].n[1] = 1, mesh->triangles[0].n[2] = 2;
  mesh->hasUvs = mesh->hasNormals = true;
  Scene s;
  s.entities.push_back(meshEntity(mesh, Transform()));
  s.entities.push_back(meshEntity(mesh, Transform()));
  s.entities.back().smooth = true;
  s.entities[1].worldFromObject = Transform::translate({0, 0, 1});
  {
    EmbreeAccelerator accel(s);
    Hit h;
    // Barycentrics (b1, b2) = (0.25, 0.5) at (0.25, 0.5, 2).
    ASSERT_TRUE(accel.intersect({{0.25, 0.5, 0}, {0, 0, 1}}, h));
    EXPECT_EQ(h.entity, 0u);
    EXPECT_EQ(h.primitive, 0u);
    EXPECT_NEAR(h.t, 2, 1e-6);
    EXPECT_NEAR(h.p.x, 0.25, 1e-6);
    EXPECT_NEAR(h.p.y, 0.5, 1e-6);
    EXPECT_EQ(h.p.z, 2); // on the plane exactly: interpolated, not o + t d
    EXPECT_NEAR(h.u, 0.5 + 0.25, 1e-6);
    EXPECT_NEAR(h.v, 0.5 + 2 * 0.5, 1e-6);
    // cross(p1 - p0, p2 - p0) = +z, but the given normals point to -z: the
    // face normal follows them; not smooth, so ns = ng.
    EXPECT_EQ(h.ng, Vec3(0, 0, -1));
    EXPECT_EQ(h.ns, h.ng);
    EXPECT_GT(h.pError, 0);
  }
  s.entities.erase(s.entities.begin());
  EmbreeAccelerator accel(s);
  Hit h;
  ASSERT_TRUE(accel.intersect({{0.25, 0.5, 0}, {0, 0, 1}}, h));
  EXPECT_NEAR(h.t, 3, 1e-6);
  Vec3 expected = normalize(Vec3(0.5 * 0.6, 0.25 * 0.6, -0.8 * 0.75 - 0.25));
  EXPECT_NEAR(h.ns.x, expected.x, 1e-6);
  EXPECT_NEAR(h.ns.y, expected.y, 1e-6);
  EXPECT_NEAR(h.ns.z, expected.z, 1e-6);
  EXPECT_EQ(h.ng, Vec3(0, 0, -1));
}

TEST(EmbreeAccelerator, DefaultTriangleUvs) {
  auto mesh = makeMesh({{0, 0, 2}, {1, 0, 2}, {0, 1, 2}}, {0, 1, 2});
  Scene s;
  s.entities.push_back(meshEntity(mesh, Transform()));
  EmbreeAccelerator accel(s);
  Hit h;
  ASSERT_TRUE(accel.intersect({{0.25, 0.5, 0}, {0, 0, 1}}, h));
  EXPECT_NEAR(h.u, 0.25, 1e-6); // corner 1 is (1, 0)
  EXPECT_NEAR(h.v, 0.5, 1e-6);  // corner 2 is (0, 1)
  EXPECT_EQ(h.ng, Vec3(0, 0, 1));
}

// A mesh with a triangle of no area stays instanced, even when one
// entity uses it: placed in float, its collinear corners would make a
// sliver rays could hit. Without such a triangle it is placed; both find
// the same hits.
TEST(EmbreeAccelerator, MeshWithAZeroAreaTriangleStaysInstanced) {
  const Transform place = Transform::translate({0.3, -0.2, 5}) * Transform::rotate({1, 1, 0}, 20);
  auto proper = makeMesh({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {2, 0, 0}, {3, 1, 0}, {4, 2, 0}},
                         {0, 1, 2});
  auto withCollinear = makeMesh(
      {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {2, 0, 0}, {3, 1, 0}, {4, 2, 0}}, {0, 1, 2, 3, 4, 5});
  for (const auto &[mesh, instanced] : {std::pair{proper, false}, std::pair{withCollinear, true}}) {
    Scene s;
    s.entities.push_back(meshEntity(mesh, place));
    s.textures.push_back({});
    EmbreeAccelerator accel(s);
    EXPECT_EQ(accel.stats().instances, instanced ? 1u : 0u);
    Hit h;
    ASSERT_TRUE(accel.intersect({{0.3, -0.2, 0}, {0, 0, 1}}, h));
    EXPECT_EQ(h.primitive, 0u);
    EXPECT_NEAR(h.t, 5, 1e-6);
  }
}

TEST(EmbreeAccelerator, InstancesShareOneMesh) {
  auto sphere = makeJitteredSphere(3, 0.0, 1);
  Scene s;
  for (int i = 0; i < 50; ++i)
    s.entities.push_back(meshEntity(sphere, Transform::translate({3.0 * i, 0, 10})));
  EmbreeAccelerator accel(s);
  EXPECT_EQ(accel.stats().instances, 50u);
  EXPECT_EQ(accel.stats().primitives, sphere->triangles.size());
  for (int i = 0; i < 50; i += 7) {
    Hit h;
    ASSERT_TRUE(accel.intersect({{3.0 * i, 0.1, 0}, {0, 0, 1}}, h));
    EXPECT_EQ(h.entity, static_cast<uint32_t>(i));
    EXPECT_NEAR(h.t, 9, 2e-2);
  }
}

TEST(EmbreeAccelerator, SkipsMeshlessAndEmptyMeshEntities) {
  Scene s;
  s.entities.push_back(meshEntity(nullptr, Transform()));
  s.entities.push_back(meshEntity(std::make_shared<MeshData>(), Transform()));
  s.entities.push_back(shapeEntity(ShapeKind::Sphere, Transform::translate({0, 0, 5})));
  EmbreeAccelerator accel(s);
  Hit h;
  ASSERT_TRUE(accel.intersect({{0, 0, 0}, {0, 0, 1}}, h));
  EXPECT_EQ(h.entity, 2u);
}

TEST(EmbreeAccelerator, CoherentBatchOfAnyLength) {
  Scene s = mixedScene();
  // An untransformed mesh too: its hits take the SIMD fill.
  const uint32_t placed = static_cast<uint32_t>(s.entities.size());
  s.entities.push_back(
      meshEntity(makeMesh({{-3, 0.5, 4.5}, {1, 0.5, 4.5}, {1, 0.8, 4.5}, {-3, 0.8, 4.5}},
                          {0, 2, 1, 0, 3, 2}),
                 Transform()));
  EmbreeAccelerator accel(s);
  size_t placedHits = 0;
  for (size_t count : {1u, 7u, 8u, 9u, 17u, 255u, 256u, 257u, 520u}) {
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i)
      rays.push_back({{0, 0, -2}, {-0.3 + 0.05 * static_cast<double>(i % 13), 0.1, 1}});
    std::vector<Hit> hits(count);
    std::vector<uint8_t> found(count, 9);
    accel.intersectCoherent(rays.data(), count, hits.data(), found.data());
    for (size_t i = 0; i < count; ++i) {
      Hit h;
      bool hit = accel.intersect(rays[i], h);
      ASSERT_EQ(found[i], hit ? 1 : 0);
      if (hit) expectSameHit(hits[i], h);
      placedHits += hit && h.entity == placed;
    }
  }
  EXPECT_GT(placedHits, 100u);
}

} // namespace
} // namespace lray
