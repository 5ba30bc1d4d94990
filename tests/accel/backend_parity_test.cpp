// Geometry through both backends (SPEC 8): the same scene gives the same
// closest entity, t and hit record from Embree and from the kd-tree, and
// both agree with a brute-force double-precision reference.
#include "accel/accelerator.h"
#include "shape_params.h"

#include "accel_test_scenes.h"
#include "geometry/spawn.h"

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

std::string backendCaseName(const ::testing::TestParamInfo<BackendKind> &param) {
  return backendName(param.param);
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendParity,
                         ::testing::Values(BackendKind::Embree, BackendKind::KdTree),
                         backendCaseName);

} // namespace
} // namespace lray
