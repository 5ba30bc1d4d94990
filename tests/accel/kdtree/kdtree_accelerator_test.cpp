// Tests for src/accel/kdtree/kdtree_accelerator.h: the two-level backend
// against a brute-force loop over the same shared shape code.
#include "accel/kdtree/kdtree_accelerator.h"

#include "geometry/float_frame.h"
#include "geometry/shape.h"
#include "math/spawn.h"
#include "hit_expect.h"
#include "accel/kdtree/kdtree_test_util.h"
#include "shading/quad_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace lray {
namespace {

using kdtest::Rng;

Entity shape(ShapeKind kind, const Transform &worldFromObject) {
  Entity e;
  e.shape = makeShape(kind);
  e.worldFromObject = worldFromObject;
  return e;
}

Entity meshEntity(const MeshDataPtr &mesh, const Transform &worldFromObject) {
  Entity e = shape(ShapeKind::Mesh, worldFromObject);
  e.mesh = mesh;
  return e;
}

// Closest hit by testing every entity and every triangle.
bool bruteForce(const Scene &scene, const Ray &ray, Hit &hit) {
  bool found = false;
  double tMax = ray.tMax;
  for (uint32_t i = 0; i < scene.entities.size(); ++i) {
    const Entity &e = scene.entities[i];
    Ray bounded = ray;
    bounded.tMax = tMax;
    if (e.kind() != ShapeKind::Mesh) {
      Hit h;
      if (intersectShape(e, i, bounded, h)) {
        hit = h;
        tMax = h.t;
        found = true;
      }
      continue;
    }
    Ray objectRay = e.worldFromObject.inverse().applyRay(bounded);
    WatertightRay wray(objectRay);
    const MeshData &m = *e.mesh;
    for (uint32_t t = 0; t < m.triangleIndices.size() / 3; ++t) {
      TriangleHitParams p;
      if (intersectTriangle(wray, toVec3(m.positions[m.triangleIndices[3 * t]]),
                            toVec3(m.positions[m.triangleIndices[3 * t + 1]]),
                            toVec3(m.positions[m.triangleIndices[3 * t + 2]]), tMax, p)) {
        tMax = p.t;
        fillTriangleHit(e, i, t, p.t, p.b1, p.b2, ray, floatFrameOrigin(scene), hit);
        found = true;
      }
    }
  }
  return found;
}

/// A pinhole camera's rays from `eye` as the renderer issues them: tile by
/// tile (16x16, row-major), pixel (x, y) through (x - cx + 0.5, cy - y - 0.5,
/// width * depth) / width.
std::vector<Ray> cameraTiles(int width, int height, const Vec3 &eye, int cx, int cy,
                             double depth) {
  std::vector<Ray> rays;
  for (int ty = 0; ty < height; ty += 16)
    for (int tx = 0; tx < width; tx += 16)
      for (int y = ty; y < ty + 16; ++y)
        for (int x = tx; x < tx + 16; ++x)
          rays.push_back({eye, {(x - cx + 0.5) / width, (cy - y - 0.5) / width, depth}});
  return rays;
}

/// intersectCoherent of `rays` in runs of 256 (a tile's), each ray's find
/// checked against intersect()'s, bit for bit: per ray the entity it hit,
/// or -1.
std::vector<int> coherentMatchesSingle(const KdTreeAccelerator &accel,
                                       const std::vector<Ray> &rays) {
  std::vector<Hit> batch(rays.size());
  std::vector<uint8_t> found(rays.size(), 9);
  for (size_t first = 0; first < rays.size(); first += 256) {
    const size_t count = std::min<size_t>(256, rays.size() - first);
    accel.intersectCoherent(rays.data() + first, count, batch.data() + first,
                            found.data() + first);
  }
  std::vector<int> entity(rays.size(), -1);
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    const bool f = accel.intersect(rays[i], single);
    EXPECT_EQ(found[i], f ? 1 : 0) << i;
    if (!f || found[i] != 1) continue;
    testing::expectSameHit(batch[i], single);
    entity[i] = static_cast<int>(single.entity);
  }
  return entity;
}

Scene mixedScene() {
  Scene scene;
  MeshDataPtr ball = kdtest::makeJitteredSphere(12, 24, 0.1, 1);
  scene.entities.push_back(meshEntity(ball, Transform::identity()));
  scene.entities.push_back(
      meshEntity(ball, Transform::translate({4, 0, 0}) * Transform::rotate({1, 1, 0}, 30) *
                           Transform::scale(1, 2, 0.5)));
  scene.entities.push_back(shape(ShapeKind::Sphere, Transform::translate({-3, 1, 0})));
  scene.entities.push_back(shape(ShapeKind::Cube, Transform::translate({0, -3, 1}) *
                                                      Transform::rotate({0, 1, 0}, 20)));
  scene.entities.push_back(shape(ShapeKind::Cylinder, Transform::translate({0, 3, 0})));
  scene.entities.push_back(shape(ShapeKind::Cone, Transform::translate({-3, -3, 0})));
  scene.textures.emplace_back();
  scene.pigments.emplace_back();
  return scene;
}

TEST(KdTreeAccelerator, MatchesBruteForceOnMixedScene) {
  Scene scene = mixedScene();
  KdTreeAccelerator accel(scene);
  EXPECT_EQ(accel.meshTreeCount(), 1u); // the copy shares its tree
  AcceleratorStats stats = accel.stats();
  EXPECT_EQ(stats.instances, 2u);
  EXPECT_EQ(stats.primitives, 4u + scene.entities[0].mesh->triangleIndices.size() / 3);
  EXPECT_GT(stats.memoryBytes, 0u);
  EXPECT_GE(stats.buildSeconds, 0);

  Rng rng(2);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    Vec3 o = rng.inBox({-8, -8, -8}, {8, 8, 8});
    Ray ray{o, rng.inBox({-4, -4, -1}, {5, 4, 1}) - o};
    if (i % 4 == 0) ray.tMax = rng.uniform(0, 1.2);
    Hit expected, got;
    bool e = bruteForce(scene, ray, expected);
    bool g = accel.intersect(ray, got);
    ASSERT_EQ(e, g) << i;
    EXPECT_EQ(e, accel.occluded(ray)) << i;
    if (!e) continue;
    ++hits;
    EXPECT_EQ(expected.entity, got.entity) << i;
    EXPECT_EQ(expected.primitive, got.primitive) << i;
    EXPECT_NEAR(expected.t, got.t, 1e-12 * std::max(1.0, expected.t)) << i;
    EXPECT_NEAR(length(expected.p - got.p), 0, 1e-9);
    EXPECT_NEAR(dot(expected.ng, got.ng), 1, 1e-9);
  }
  EXPECT_GT(hits, 1000);

  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) rays.push_back({{-8, 0.1 * i - 3, 0.05}, {1, 0, 0}});
  std::vector<Hit> batch(rays.size());
  std::vector<uint8_t> found(rays.size()), blocked(rays.size());
  accel.intersectCoherent(rays.data(), rays.size(), batch.data(), found.data());
  accel.occludedCoherent(rays.data(), rays.size(), blocked.data(), nullptr);
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    bool f = accel.intersect(rays[i], single);
    EXPECT_EQ(found[i], f ? 1 : 0);
    EXPECT_EQ(blocked[i], f ? 1 : 0);
    if (f) {
      EXPECT_EQ(batch[i].t, single.t);
    }
  }
}

// intersectCoherent walks the trees by the general loop, intersect() by the
// start-side descent where a tree is big enough: every field of every hit
// must agree, at any batch length, on the identity mesh, the instance,
// analytic shapes and misses.
TEST(KdTreeAccelerator, CoherentBatchMatchesSingleRaysBitForBit) {
  Scene scene = mixedScene();
  KdTreeAccelerator accel(scene);
  Rng rng(5);
  std::vector<Ray> rays;
  for (int i = 0; i < 1500; ++i) {
    Vec3 o = rng.inBox({-8, -8, -8}, {8, 8, 8});
    rays.push_back({o, rng.inBox({-4, -4, -1}, {5, 4, 1}) - o});
    if (i % 5 == 0) rays.back().tMax = rng.uniform(0, 1.2);
  }
  int kinds[3] = {0, 0, 0}; // identity mesh, instance, analytic
  size_t first = 0;
  for (size_t count : {1u, 31u, 32u, 33u, 64u, 100u, 257u, 982u}) {
    ASSERT_LE(first + count, rays.size());
    std::vector<Hit> batch(count);
    std::vector<uint8_t> found(count, 9);
    accel.intersectCoherent(rays.data() + first, count, batch.data(), found.data());
    for (size_t i = 0; i < count; ++i) {
      Hit single;
      bool f = accel.intersect(rays[first + i], single);
      ASSERT_EQ(found[i], f ? 1 : 0) << first + i;
      if (!f) continue;
      testing::expectSameHit(batch[i], single);
      ++kinds[single.entity < 2 ? single.entity : 2];
    }
    first += count;
  }
  EXPECT_GT(kinds[0], 100);
  EXPECT_GT(kinds[1], 100);
  EXPECT_GT(kinds[2], 100);
}

// A scene of few entities is tested as a list of boxes (flat_instances.h),
// a larger one walks the top-level tree: the mixed scene with spheres far
// beyond the rays' reach added past the list's limit must give the same
// hits and shadows, bit for bit, single and in batches.
TEST(KdTreeAccelerator, FewEntitiesAsAListMatchTheTreeWalk) {
  Scene few = mixedScene(), many = mixedScene();
  ASSERT_LE(few.entities.size(), FlatInstances::kMaxInstances);
  while (many.entities.size() <= FlatInstances::kMaxInstances)
    many.entities.push_back(shape(
        ShapeKind::Sphere, Transform::translate({200, 10.0 * many.entities.size(), 0})));
  KdTreeAccelerator list(few), tree(many);
  Rng rng(8);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    Vec3 o = rng.inBox({-8, -8, -8}, {8, 8, 8});
    rays.push_back({o, rng.inBox({-4, -4, -1}, {5, 4, 1}) - o});
    rays.back().tMax = i % 4 == 0 ? rng.uniform(0, 1.2) : 3; // short of the far spheres
  }
  int hits = 0;
  for (const Ray &ray : rays) {
    Hit a, b;
    const bool fa = list.intersect(ray, a);
    ASSERT_EQ(fa, tree.intersect(ray, b));
    EXPECT_EQ(list.occluded(ray), tree.occluded(ray));
    if (!fa) continue;
    ++hits;
    testing::expectSameHit(a, b);
  }
  EXPECT_GT(hits, 500);
  std::vector<Hit> batchA(rays.size()), batchB(rays.size());
  std::vector<uint8_t> foundA(rays.size()), foundB(rays.size());
  list.intersectCoherent(rays.data(), rays.size(), batchA.data(), foundA.data());
  tree.intersectCoherent(rays.data(), rays.size(), batchB.data(), foundB.data());
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(foundA[i], foundB[i]) << i;
    if (foundA[i]) {
      testing::expectSameHit(batchA[i], batchB[i]);
    }
  }
}

// A camera's rays into a list of a few entities (a pigments-like scene:
// a floor, still spheres, two of them in the same place, one in front of
// another, a cube) go four at a time, each ray's boxes in its own order,
// the rays that test the same sphere next tested together
// (KdTreeAccelerator::nearestInList): the same hits as one ray at a time,
// bit for bit, the coincident spheres' ties included, and for rays with a
// direction component 0 too.
TEST(KdTreeAccelerator, ACamerasRaysInFoursMatchSingleRays) {
  Scene scene;
  testing::addQuad(scene,
                   {Vec3f(-100, 0, -100), Vec3f(-100, 0, 100), Vec3f(100, 0, 100),
                    Vec3f(100, 0, -100)},
                   0);
  for (int i = 0; i < 4; ++i)
    scene.entities.push_back(
        shape(ShapeKind::Sphere, Transform::translate({2.2 * i - 3.3, 1, 0})));
  // The second sphere again, exactly where it is.
  scene.entities.push_back(scene.entities[2]);
  scene.entities.push_back(shape(ShapeKind::Sphere, Transform::translate({0.1, 0.5, -1.5}) *
                                                        Transform::scale(0.5, 0.5, 0.5)));
  scene.entities.push_back(shape(ShapeKind::Cube, Transform::translate({-2.5, 0.4, -3}) *
                                                      Transform::scale(0.4, 0.4, 0.4)));
  scene.textures.emplace_back();
  scene.pigments.emplace_back();
  ASSERT_LE(scene.entities.size(), FlatInstances::kMaxInstances);
  KdTreeAccelerator accel(scene);
  ASSERT_FALSE(accel.usesPackets());

  // 128x72 camera rays from above the floor, looking down at the spheres;
  // then rays along the axes (direction components 0).
  std::vector<Ray> rays = cameraTiles(128, 72, {0, 3.2, -11}, 64, 20, 1);
  for (int i = 0; i < 64; ++i) {
    const double y = 0.05 * i;
    rays.push_back({{-8, y, 0.02 * i}, {1, 0, 0}});
    rays.push_back({{-1.1 + 0.01 * i, y, -8}, {0, 0, 2}});
  }
  int byEntity[8] = {};
  for (const int e : coherentMatchesSingle(accel, rays))
    if (e >= 0) ++byEntity[e];
  // The floor, every sphere and the cube are hit; of the coincident pair
  // the first in the list, which both walks test first, wins every tie.
  for (int e : {0, 1, 2, 3, 4, 6, 7}) EXPECT_GT(byEntity[e], 20) << e;
  EXPECT_EQ(byEntity[5], 0);
}

// A scene of more entities than the list takes but few enough for a fan
// (ray_fan.h): a camera's runs of rays test only the entities their fan
// may cross, and must find what single rays walking the top-level tree
// find, bit for bit, in tiles where the fan forms and in those where a
// direction's sign changes (the whole walk).
TEST(KdTreeAccelerator, CameraRunsCulledByTheirFanMatchSingleRays) {
  Scene scene;
  const ShapeKind kinds[] = {ShapeKind::Sphere, ShapeKind::Cube, ShapeKind::Cylinder,
                             ShapeKind::Cone, ShapeKind::Torus};
  for (int i = 0; i < 20; ++i) {
    const double a = i * 2 * kPi / 20;
    scene.entities.push_back(shape(kinds[i % 5], Transform::translate({2.5 * std::cos(a),
                                                                       2.5 * std::sin(a), 0}) *
                                                     Transform::scale(0.4, 0.4, 0.4)));
  }
  scene.entities.push_back(meshEntity(kdtest::makeJitteredSphere(6, 12, 0.1, 7),
                                      Transform::translate({0.5, 0.3, 1})));
  scene.textures.emplace_back();
  scene.pigments.emplace_back();
  KdTreeAccelerator accel(scene);
  ASSERT_FALSE(accel.usesPackets());

  // 96x64 camera rays from z = -8; the middle tiles' rays change the sign
  // of x or y.
  std::vector<Ray> rays = cameraTiles(96, 64, {0.1, 0.2, -8}, 50, 30, 1);
  int hits = 0, meshHits = 0;
  for (const int e : coherentMatchesSingle(accel, rays)) {
    if (e < 0) continue;
    ++hits;
    meshHits += e == 20;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(meshHits, 50);
}

// Packets (a scene with a large mesh): intersectCoherent and
// occludedCoherent must agree with single rays field for field, for a
// camera's tiles (rays in rows of 16, as the renderer issues them), the
// shadow rays from their hits to a light, and batches of unrelated rays
// (each lane on its own), over the identity mesh, a transformed copy, a
// small mesh below the packets' size and analytic shapes (one of them met
// after a farther triangle).
TEST(KdTreeAccelerator, PacketsMatchSingleRaysBitForBit) {
  Scene scene = mixedScene();
  MeshDataPtr big = kdtest::makeJitteredSphere(80, 160, 0.1, 6);
  scene.entities[0].mesh = big;
  scene.entities[1].mesh = big;
  scene.entities.push_back(meshEntity(kdtest::makeJitteredSphere(6, 12, 0.1, 7),
                                      Transform::translate({2, 2, -2})));
  // A sphere in front of the big mesh, inside its bounds: met after it in
  // their top-level leaf, nearer than its triangles.
  scene.entities.push_back(shape(ShapeKind::Sphere, Transform::translate({0.3, 0.1, -1.2}) *
                                                        Transform::scale(0.4, 0.4, 0.4)));
  KdTreeAccelerator accel(scene);
  ASSERT_TRUE(accel.usesPackets());
  ASSERT_EQ(accel.meshTreeCount(), 2u);

  // 64x48 camera rays from z = -4.
  std::vector<Ray> rays = cameraTiles(64, 48, {0.3, 0.1, -4}, 32, 24, 1.5);
  Rng rng(9);
  for (int i = 0; i < 2500; ++i) {
    Vec3 o = rng.inBox({-8, -8, -8}, {8, 8, 8});
    rays.push_back({o, rng.inBox({-4, -4, -1}, {5, 4, 1}) - o});
    if (i % 5 == 0) rays.back().tMax = rng.uniform(0, 1.2);
  }
  std::vector<Hit> batch(rays.size());
  std::vector<uint8_t> found(rays.size(), 9);
  std::vector<Ray> shadowRays;
  int kinds[4] = {0, 0, 0, 0}; // identity mesh, copy, analytic, small mesh
  for (size_t first = 0; first < rays.size(); first += 256) {
    const size_t count = std::min<size_t>(256, rays.size() - first);
    accel.intersectCoherent(rays.data() + first, count, batch.data() + first,
                            found.data() + first);
  }
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    bool f = accel.intersect(rays[i], single);
    ASSERT_EQ(found[i], f ? 1 : 0) << i;
    if (!f) continue;
    testing::expectSameHit(batch[i], single);
    ++kinds[single.entity < 2 ? single.entity : single.entity == 6 ? 3 : 2];
    shadowRays.push_back(spawnRayTo(single, {-3, 9, -9}));
  }
  EXPECT_GT(kinds[0], 1500);
  EXPECT_GT(kinds[1], 100);
  EXPECT_GT(kinds[2], 200);
  EXPECT_GT(kinds[3], 40);

  std::vector<uint8_t> blocked(shadowRays.size(), 9);
  for (size_t first = 0; first < shadowRays.size(); first += 253) {
    const size_t count = std::min<size_t>(253, shadowRays.size() - first);
    accel.occludedCoherent(shadowRays.data() + first, count, blocked.data() + first, nullptr);
  }
  int shadowed = 0;
  for (size_t i = 0; i < shadowRays.size(); ++i) {
    const bool single = accel.occluded(shadowRays[i]);
    ASSERT_EQ(blocked[i], single ? 1 : 0) << i;
    shadowed += single;
  }
  EXPECT_GT(shadowed, 500);
  EXPECT_LT(shadowed, static_cast<int>(shadowRays.size()) - 500);
}

// Rays from inside transformed instances of a closed mesh, aimed exactly at
// world-space vertices and edge midpoints: the backend must never miss.
TEST(KdTreeAccelerator, WatertightProbeThroughInstancesHasNoMisses) {
  MeshDataPtr ball = kdtest::makeJitteredSphere(40, 80, 0.05, 3);
  Scene scene;
  Transform placed = Transform::translate({10, -2, 3}) * Transform::rotate({1, 2, 3}, 37) *
                     Transform::scale(2, 3, 1.5);
  scene.entities.push_back(meshEntity(ball, Transform::identity()));
  scene.entities.push_back(meshEntity(ball, placed));
  KdTreeAccelerator accel(scene);
  Rng rng(4);
  const auto &pos = ball->positions;
  const auto &idx = ball->triangleIndices;
  int misses = 0;
  const int kRays = 40000; // 1e5 more through the tree alone in KdTree tests
  for (int i = 0; i < kRays; ++i) {
    const Entity &e = scene.entities[i % 2];
    uint32_t tri = static_cast<uint32_t>(rng.nextBits() % (idx.size() / 3));
    int corner = static_cast<int>(rng.nextBits() % 3);
    Vec3 a = toVec3(pos[idx[3 * tri + corner]]);
    Vec3 b = toVec3(pos[idx[3 * tri + (corner + 1) % 3]]);
    Vec3 target = e.worldFromObject.applyPoint(i % 4 < 2 ? a : (a + b) * 0.5);
    Vec3 o = e.worldFromObject.applyPoint(rng.inBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}));
    Ray ray{o, target - o};
    Hit hit;
    if (!accel.intersect(ray, hit) || hit.entity != static_cast<uint32_t>(i % 2)) ++misses;
    if (i % 8 == 0 && !accel.occluded(ray)) ++misses;
  }
  EXPECT_EQ(misses, 0);
}

// A floor of two triangles is a tree of one leaf, tested without a walk
// to clip the ray to its box; a shadow ray that starts outside the box on
// an axis and does not move towards it is dropped before the test.
TEST(KdTreeAccelerator, AFloorsShadowRaysAgreeWithBruteForce) {
  Scene scene;
  const std::array<Vec3f, 4> floor{Vec3f(-100, 0, -100), Vec3f(-100, 0, 100),
                                   Vec3f(100, 0, 100), Vec3f(100, 0, -100)};
  testing::addQuad(scene, floor, 0);
  testing::addQuad(scene, floor, 0,
                   Transform::translate({0, 4, 0}) * Transform::rotate({1, 0, 1}, 25));
  // Enough small spheres over it for the shadow rays to go in packets.
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 80; ++j)
      scene.entities.push_back(shape(
          ShapeKind::Sphere, Transform::translate({0.6 * i - 24, 1 + 0.02 * j, 0.6 * j - 24}) *
                                 Transform::scale(0.1, 0.1, 0.1)));
  scene.textures.emplace_back();
  scene.pigments.emplace_back();
  KdTreeAccelerator accel(scene);
  ASSERT_TRUE(accel.usesPackets());

  Rng rng(34);
  std::vector<Ray> rays;
  for (int i = 0; i < 1200; ++i) {
    Vec3 o = rng.inBox({-30, -3, -30}, {30, 8, 30});
    // On the floor, a hair above or below it, or anywhere.
    const double heights[] = {0, 1e-12, -1e-12, 0x1p-1074, o.y};
    o.y = heights[i % 5];
    Vec3 d = rng.direction() * rng.uniform(0.5, 40);
    if (i % 7 == 0) d.y = 0; // along the floor
    if (i % 11 == 0) d = {0, (i % 2 ? 1 : -1) * rng.uniform(1, 9), 0};
    rays.push_back({o, d, 0, 1});
  }
  std::vector<uint8_t> coherent(rays.size());
  accel.occludedCoherent(rays.data(), rays.size(), coherent.data(), nullptr);
  size_t blocked = 0, selfHitsDropped = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray &ray = rays[i];
    // A ray that starts off the flat floor and does not move towards it is
    // not blocked by it, though the triangle test alone finds it at t of
    // 1e-15 from a denormal height; brute force is asked past t = 1e-9.
    const bool leaves = (ray.o.y > 0 && ray.d.y >= 0) || (ray.o.y < 0 && ray.d.y <= 0);
    Ray late = ray;
    late.tMin = 1e-9;
    Hit hit;
    const bool expected = bruteForce(scene, leaves ? late : ray, hit);
    if (leaves && !expected && bruteForce(scene, ray, hit) && hit.entity == 0) ++selfHitsDropped;
    EXPECT_EQ(accel.occluded(ray), expected) << "ray " << i;
    EXPECT_EQ(coherent[i] != 0, expected) << "ray " << i;
    blocked += expected;
  }
  // Both answers are common, and the triangle test's own self-hits are
  // among the rays.
  EXPECT_GT(blocked, rays.size() / 5);
  EXPECT_LT(blocked, rays.size() * 4 / 5);
  EXPECT_GT(selfHitsDropped, 0u);
}

TEST(KdTreeAccelerator, EmptySceneMissesEverything) {
  Scene scene;
  KdTreeAccelerator accel(scene);
  Hit hit;
  EXPECT_FALSE(accel.intersect({{0, 0, 0}, {0, 0, 1}}, hit));
  EXPECT_FALSE(accel.occluded({{0, 0, 0}, {1, 1, 1}}));
  EXPECT_EQ(accel.stats().primitives, 0u);
  EXPECT_EQ(accel.stats().instances, 0u);

  // A mesh without triangles is no primitive either.
  scene.entities.push_back(meshEntity(std::make_shared<MeshData>(), Transform::identity()));
  KdTreeAccelerator withEmptyMesh(scene);
  EXPECT_FALSE(withEmptyMesh.intersect({{0, 0, -5}, {0, 0, 1}}, hit));
  EXPECT_TRUE(withEmptyMesh.topLevelTree().empty());
}

} // namespace
} // namespace lray
