// Geometry through both backends (README.md, "Accuracy, and the two backends"): the same scene
// gives the same closest entity, t and hit record from Embree and from the kd-tree, and both agree
// with a brute-force double-precision reference.
#include "render/backends.h"
#include "accel/kdtree/kdtree_accelerator.h"
#include "shape_params.h"

#include "accel_test_scenes.h"
#include "geometry/shape.h"
#include "math/spawn.h"

#include <gtest/gtest.h>

#include <random>

namespace lray {
namespace {

using testing::bruteForce;
using testing::makeJitteredSphere;
using testing::meshEntity;
using testing::shapeEntity;

Scene parityScene() {
  Scene s;
  auto ball = makeJitteredSphere(1, 0.05, 3);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1), sc(0.3, 1);
  for (int i = 0; i < 60; ++i) {
    Transform xf = Transform::translate({4 * u(rng), 4 * u(rng), 8 + 4 * u(rng)}) *
                   Transform::rotate({u(rng), u(rng), 1}, 180 * u(rng)) *
                   Transform::scale(sc(rng), sc(rng), sc(rng));
    if (i % 5 == 4) s.entities.push_back(meshEntity(ball, xf));
    else s.entities.push_back(shapeEntity(static_cast<ShapeKind>(i % 4), xf));
    setOpen(s.entities.back(), i % 7 == 0);
  }
  s.textures.push_back({});
  return s;
}

class BackendParity : public ::testing::TestWithParam<BackendKind> {};

TEST_P(BackendParity, AgreesWithBruteForceAndSpawnsCleanly) {
  Scene s = parityScene();
  auto accel = makeAccelerator(GetParam(), s);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    Ray ray{{u(rng), u(rng), -3}, {0.5 * u(rng), 0.5 * u(rng), 1}};
    auto [entity, t] = bruteForce(s, ray);
    Hit h;
    bool hit = accel->intersect(ray, h);
    ASSERT_EQ(hit, entity >= 0) << backendName(GetParam()) << " ray " << i;
    ASSERT_EQ(accel->occluded(ray), hit) << i;
    if (!hit) continue;
    ++hits;
    ASSERT_EQ(h.entity, static_cast<uint32_t>(entity)) << i;
    ASSERT_NEAR(h.t, t, 1e-5 * t) << i;
    // A reflected ray leaves without finding its own surface right away.
    Vec3 refl = ray.d - h.ng * (2 * dot(ray.d, h.ng));
    Hit h2;
    if (accel->intersect(spawnRay(h, refl), h2) && h2.entity == h.entity) {
      EXPECT_GT(h2.t, 1e-6) << i;
    }
  }
  EXPECT_GT(hits, 300);
}

TEST(BackendPair, EmbreeAndKdTreeReturnTheSameHits) {
  Scene s = parityScene();
  auto embree = makeAccelerator(BackendKind::Embree, s);
  auto kdtree = makeAccelerator(BackendKind::KdTree, s);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  int analytic = 0, mesh = 0;
  for (int i = 0; i < 3000; ++i) {
    Ray ray{{u(rng), u(rng), -3}, {0.5 * u(rng), 0.5 * u(rng), 1}};
    Hit a, b;
    bool ha = embree->intersect(ray, a), hb = kdtree->intersect(ray, b);
    ASSERT_EQ(ha, hb) << i;
    if (!ha) continue;
    ASSERT_EQ(a.entity, b.entity) << i;
    if (s.entities[a.entity].kind() != ShapeKind::Mesh) {
      // Same shape code on the same double ray: bit-identical.
      ++analytic;
      EXPECT_EQ(a.t, b.t);
      EXPECT_EQ(a.p, b.p);
      EXPECT_EQ(a.ng, b.ng);
      EXPECT_EQ(a.u, b.u);
    } else {
      // Float (Embree) and double (kd-tree) triangle tests: same triangle,
      // points on it within float precision (more along grazing rays).
      ++mesh;
      EXPECT_EQ(a.primitive, b.primitive);
      EXPECT_NEAR(a.t, b.t, 1e-5 * a.t);
      EXPECT_LT(length(a.p - b.p), 1e-4 * (1 + length(a.p)));
      EXPECT_EQ(a.ng, b.ng);
    }
  }
  EXPECT_GT(analytic, 100);
  EXPECT_GT(mesh, 20);
}

// Planes are unbounded: both backends keep them out of their trees and test
// them on every ray (accel/unbounded_shapes.h). Tori join them here: the
// newest shapes, in the same bit-identity check.
Scene parityScenePlusPlanes() {
  Scene s = parityScene();
  for (int i = 0; i < 4; ++i) {
    Entity torus = shapeEntity(ShapeKind::Torus, Transform::translate({1.5 * i - 2.2, 0.8, 6}) *
                                                     Transform::rotate({1, 0.2 * i, 0}, 60));
    std::get<Torus>(torus.shape).minor = 0.2 + 0.1 * i;
    s.entities.push_back(torus);
  }
  Entity floor = shapeEntity(ShapeKind::Plane, Transform::translate({0, -2.5, 0}));
  s.entities.insert(s.entities.begin() + 7, floor);
  // Tilted behind everything; facing away from the rays' origin side too.
  s.entities.push_back(shapeEntity(ShapeKind::Plane, Transform::translate({0, 0, 14}) *
                                                         Transform::rotate({1, 0.3, 0}, 80)));
  return s;
}

TEST_P(BackendParity, PlanesAgreeWithBruteForce) {
  Scene s = parityScenePlusPlanes();
  auto accel = makeAccelerator(GetParam(), s);
  Scene without = parityScene();
  EXPECT_EQ(accel->stats().primitives,
            makeAccelerator(GetParam(), without)->stats().primitives + 2 + 4);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int planeHits = 0, otherHits = 0;
  for (int i = 0; i < 3000; ++i) {
    Ray ray{{u(rng), u(rng), -3}, {0.6 * u(rng), 0.6 * u(rng), 1}};
    auto [entity, t] = bruteForce(s, ray);
    Hit h;
    bool hit = accel->intersect(ray, h);
    ASSERT_EQ(hit, entity >= 0) << i;
    ASSERT_EQ(accel->occluded(ray), hit) << i;
    if (!hit) continue;
    ASSERT_EQ(h.entity, static_cast<uint32_t>(entity)) << i;
    ASSERT_NEAR(h.t, t, 1e-5 * t) << i;
    if (s.entities[h.entity].kind() == ShapeKind::Plane) {
      ++planeHits;
      // A shadow ray towards a point beyond the plane is blocked by it.
      Ray through = spawnRay(h, ray.d);
      EXPECT_FALSE(accel->intersect(through, h) && h.entity == static_cast<uint32_t>(entity));
    } else {
      ++otherHits;
    }
  }
  EXPECT_GT(planeHits, 300);
  EXPECT_GT(otherHits, 300);
}

TEST(BackendPair, PlanesAndToriGiveBitIdenticalHitsAndBatches) {
  Scene s = parityScenePlusPlanes();
  auto embree = makeAccelerator(BackendKind::Embree, s);
  auto kdtree = makeAccelerator(BackendKind::KdTree, s);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr size_t kBatch = 64;
  std::vector<Ray> rays(kBatch);
  std::vector<Hit> ha(kBatch), hb(kBatch);
  std::vector<uint8_t> fa(kBatch), fb(kBatch), oa(kBatch), ob(kBatch);
  int planeHits = 0, torusHits = 0;
  for (int batch = 0; batch < 40; ++batch) {
    for (Ray &r : rays) r = {{u(rng), u(rng), -3}, {0.6 * u(rng), 0.6 * u(rng), 1}};
    embree->intersectCoherent(rays.data(), kBatch, ha.data(), fa.data());
    kdtree->intersectCoherent(rays.data(), kBatch, hb.data(), fb.data());
    embree->occludedCoherent(rays.data(), kBatch, oa.data(), nullptr);
    kdtree->occludedCoherent(rays.data(), kBatch, ob.data(), nullptr);
    for (size_t i = 0; i < kBatch; ++i) {
      Hit single;
      ASSERT_EQ(fa[i], fb[i]) << batch << " " << i;
      ASSERT_EQ(oa[i], fa[i]);
      ASSERT_EQ(ob[i], fb[i]);
      ASSERT_EQ(embree->intersect(rays[i], single), fa[i] != 0);
      if (!fa[i]) continue;
      ASSERT_EQ(ha[i].entity, hb[i].entity);
      EXPECT_EQ(single.entity, ha[i].entity);
      const ShapeKind kind = s.entities[ha[i].entity].kind();
      if (kind != ShapeKind::Plane && kind != ShapeKind::Torus) continue;
      ++(kind == ShapeKind::Plane ? planeHits : torusHits);
      EXPECT_EQ(ha[i].ng, hb[i].ng);
      EXPECT_EQ(ha[i].t, hb[i].t);
      EXPECT_EQ(ha[i].p, hb[i].p);
      EXPECT_EQ(ha[i].u, hb[i].u);
      EXPECT_EQ(ha[i].v, hb[i].v);
    }
  }
  EXPECT_GT(planeHits, 500);
  EXPECT_GT(torusHits, 50);
}

// occludedCoherent names what blocked a ray where that is an analytic
// entity, for the integrator to test first on the same point's next shadow
// ray (shading/integrator_impl.h, markClearLanes). A named entity blocks
// the ray by the test a backend calls for it (occludedAnalytic); a clear
// ray names none; a ray that only analytic entities block names one; a ray
// that only meshes and planes block names none. Both kd-tree paths: single
// rays (the small scene) and packets (with 3,600 more spheres).
TEST_P(BackendParity, OccludedCoherentNamesAnalyticBlockers) {
  for (const bool many : {false, true}) {
    SCOPED_TRACE(many ? "3,600 more spheres" : "the parity scene and planes");
    Scene s = parityScenePlusPlanes();
    for (int i = 0; i < 60 && many; ++i)
      for (int j = 0; j < 60; ++j)
        s.entities.push_back(shapeEntity(
            ShapeKind::Sphere, Transform::translate({0.15 * i - 4.5, 0.15 * j - 4.5, 5}) *
                                   Transform::scale(0.06, 0.06, 0.06)));
    auto accel = makeAccelerator(GetParam(), s);
    if (many && GetParam() == BackendKind::KdTree) {
      ASSERT_TRUE(KdTreeAccelerator(s).usesPackets());
    }
    // What the meshes and planes alone block.
    Scene others;
    for (const Entity &e : s.entities)
      if (e.isMesh() || e.kind() == ShapeKind::Plane) others.entities.push_back(e);
    others.textures.push_back({});
    auto othersAccel = makeAccelerator(GetParam(), others);
    std::mt19937_64 rng(many ? 31 : 30);
    std::uniform_real_distribution<double> u(-1, 1);
    constexpr size_t kBatch = 37; // packets and a partial one
    std::vector<Ray> rays(kBatch);
    std::vector<uint8_t> occluded(kBatch);
    std::vector<uint32_t> blockers(kBatch);
    int named = 0, analyticOnly = 0, othersOnly = 0, clear = 0;
    for (int batch = 0; batch < 60; ++batch) {
      // Shadow rays (tMax 1) from points in the scene towards a light
      // above it, neighbours close together as a tile's are.
      const Vec3 light{6 * u(rng), 9, 6 * u(rng)};
      const Vec3 corner{4 * u(rng), 4 * u(rng), 8 + 4 * u(rng)};
      for (Ray &r : rays) {
        const Vec3 o = corner + Vec3{0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)};
        r = Ray{o, light - o};
        r.tMin = 1e-9;
        r.tMax = 1;
      }
      accel->occludedCoherent(rays.data(), kBatch, occluded.data(), blockers.data());
      for (size_t i = 0; i < kBatch; ++i) {
        const Ray &ray = rays[i];
        ASSERT_EQ(occluded[i] != 0, accel->occluded(ray)) << batch << " " << i;
        bool analytic = false;
        for (const Entity &e : s.entities)
          analytic = analytic || (!e.isMesh() && e.kind() != ShapeKind::Plane &&
                                  occludedAnalytic(e, ray));
        const bool byOthers = othersAccel->occluded(ray);
        ASSERT_EQ(occluded[i] != 0, analytic || byOthers) << batch << " " << i;
        if (blockers[i] != kNoEntity) {
          ASSERT_LT(blockers[i], s.entities.size());
          const Entity &e = s.entities[blockers[i]];
          ASSERT_FALSE(e.isMesh());
          ASSERT_TRUE(occludedAnalytic(e, ray)) << batch << " " << i;
          ++named;
        } else {
          ASSERT_FALSE(analytic && !byOthers) << batch << " " << i;
        }
        analyticOnly += analytic && !byOthers;
        othersOnly += byOthers && !analytic;
        clear += !occluded[i];
      }
    }
    EXPECT_GT(analyticOnly, 100);
    EXPECT_GE(named, analyticOnly);
    EXPECT_GT(othersOnly, 20);
    EXPECT_GT(clear, 100);
  }
}

std::string backendCaseName(const ::testing::TestParamInfo<BackendKind> &param) {
  return backendName(param.param);
}

TEST(KdTreeAccelerator, PlanesStayOutOfTheTopLevelTree) {
  Scene s = parityScenePlusPlanes();
  KdTreeAccelerator accel(s);
  const Bounds3 &b = accel.topLevelTree().bounds();
  EXPECT_TRUE(isFinite(b.lo) && isFinite(b.hi));
  EXPECT_LT(b.diagonal().y, 20);
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendParity,
                         ::testing::Values(BackendKind::Embree, BackendKind::KdTree),
                         backendCaseName);

} // namespace
} // namespace lray
