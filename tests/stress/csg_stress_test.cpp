// Robustness suite, CSG (issue 20): the CSG gallery's kinds of surface (a
// cube and sphere minus rods, a lens, a bowl cut by a plane) scaled from
// 1e-4 to 1e4 and moved up to 1e5 from the origin, through both backends.
// Secondary rays leaving a CSG surface (reflected back, continuing
// through, and towards a light) must not find that surface again.
#include "geometry/csg_tree.h"
#include "math/spawn.h"
#include "geometry/csg_test_trees.h"
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace lray::stress {
namespace {

using lray::test::csgEntity;
using lray::test::leafSpec;
using lray::test::opSpec;

Scene csgScene(double offset, double scale) {
  Scene s;
  const Transform place = Transform::translate({offset, offset * 0.5, offset}) *
                          Transform::scale(scale, scale, scale);
  const Transform rodY = Transform::scale(0.4, 3, 0.4) * Transform::translate({0, -0.5, 0});
  s.entities.push_back(csgEntity(
      opSpec(CsgOp::Difference,
             {opSpec(CsgOp::Intersection,
                     {leafSpec(ShapeKind::Cube, Transform()),
                      leafSpec(ShapeKind::Sphere, Transform::scale(0.68, 0.68, 0.68))}),
              leafSpec(ShapeKind::Cylinder, rodY),
              leafSpec(ShapeKind::Cylinder, Transform::rotate({1, 0, 0}, 90) * rodY),
              leafSpec(ShapeKind::Cylinder, Transform::rotate({0, 0, 1}, 90) * rodY)},
             place * Transform::translate({-1.5, 0, 0}) * Transform::rotate({1, 1, 0}, 35))));
  s.entities.push_back(csgEntity(opSpec(
      CsgOp::Intersection,
      {leafSpec(ShapeKind::Sphere, Transform::translate({-0.6, 0, 0})),
       leafSpec(ShapeKind::Sphere, Transform::translate({0.6, 0, 0}))},
      place * Transform::rotate({0, 1, 0}, 70) * Transform::scale(1, 1.3, 1.3))));
  s.entities.push_back(csgEntity(opSpec(
      CsgOp::Intersection,
      {opSpec(CsgOp::Difference, {leafSpec(ShapeKind::Sphere, Transform()),
                                  leafSpec(ShapeKind::Sphere, Transform::scale(0.85, 0.85, 0.85))}),
       leafSpec(ShapeKind::Plane, Transform::translate({0, 0.3, 0}))},
      place * Transform::translate({1.5, 0, 0.3}) * Transform::rotate({1, 0, 0}, -40) *
          Transform::scale(0.7, 0.7, 0.7))));
  s.camera.fov = 50;
  s.camera.aspect = 4.0 / 3;
  s.camera.worldFromCamera =
      Transform::lookAt(place.applyPoint({0.3, 1.6, -3.6}), place.applyPoint({0, 0, 0}), {0, 1, 0});
  addDefaultMaterials(s);
  return s;
}

struct CsgSweepCase {
  double offset, scale;
  double target; ///< largest fraction of hits whose secondary rays re-hit the surface
};

const CsgSweepCase kCsgCases[] = {
    {0, 1e-4, 1e-4}, {0, 1e-2, 1e-4}, {0, 1, 1e-4},   {0, 1e2, 1e-4},
    {0, 1e4, 1e-3},  {1e3, 1, 1e-4},  {1e4, 1, 1e-3}, {1e5, 1, 1e-3},
};

class StressCsg : public ::testing::TestWithParam<BackendKind> {};

TEST_P(StressCsg, SecondaryRaysLeaveCsgSurfaces) {
  const int width = 160, height = 120;
  for (const CsgSweepCase &c : kCsgCases) {
    Scene scene = csgScene(c.offset, c.scale);
    auto accel = makeAccelerator(GetParam(), scene);
    std::vector<Ray> rays = cameraRays(scene, width, height);
    std::vector<Hit> hits;
    std::vector<int> ids = hitEntities(*accel, rays, &hits);
    const Vec3 light = scene.camera.worldFromCamera.applyPoint({-3 * c.scale, 4 * c.scale, 0});
    size_t surfaces = 0, rehits = 0, nonFinite = 0, carved = 0;
    const double near = 1e-6 * c.scale; // a re-hit: a surface found this close
    for (size_t i = 0; i < rays.size(); ++i) {
      if (ids[i] < 0) continue;
      const Hit &h = hits[i];
      if (!hitIsFinite(h)) {
        ++nonFinite;
        continue;
      }
      ++surfaces;
      // A carved wall: the surface of a subtracted solid.
      const CsgTree &tree = *std::get<Csg>(scene.entities[h.entity].shape).tree;
      carved += tree.leaves[h.primitive].inverted;
      const Vec3 d = rays[i].d;
      const Vec3 n = dot(h.ng, d) < 0 ? h.ng : -h.ng;
      const Vec3 back = d - n * (2 * dot(d, n));
      bool again = false;
      for (const Vec3 &dir : {back, d}) {
        Hit next;
        if (accel->intersect(spawnRay(h, dir), next) && next.t * length(dir) < near) again = true;
      }
      // Towards the light from a surface facing it: a shadow ray that finds
      // something within `near` found this surface.
      if (dot(n, light - h.p) > 0) {
        Ray shadow = spawnRayTo(h, light);
        shadow.tMax = near / length(shadow.d);
        if (accel->occluded(shadow)) again = true;
      }
      rehits += again;
    }
    const double fraction = surfaces ? double(rehits) / double(surfaces) : 0;
    std::printf("[csg] %-6s offset %-6g scale %-6g: %zu hits (%zu on carved walls), %zu re-hit "
                "(%.2e)\n",
                backendName(GetParam()).c_str(), c.offset, c.scale, surfaces, carved, rehits,
                fraction);
    EXPECT_EQ(nonFinite, 0u) << "offset " << c.offset << " scale " << c.scale;
    EXPECT_GT(surfaces, rays.size() / 3) << "offset " << c.offset << " scale " << c.scale;
    EXPECT_GT(carved, surfaces / 20) << "offset " << c.offset << " scale " << c.scale;
    EXPECT_LE(fraction, c.target) << "offset " << c.offset << " scale " << c.scale;
  }
}

// The same picture at every scale and offset: the CSG hits found at scale
// 1 and at the moved or scaled placement agree pixel for pixel (entity and
// leaf), so no placement loses or invents a surface.
TEST_P(StressCsg, MovedAndScaledCsgFindsTheSameSurfaces) {
  const int width = 120, height = 90;
  Scene base = csgScene(0, 1);
  auto baseAccel = makeAccelerator(GetParam(), base);
  std::vector<Hit> baseHits;
  std::vector<int> baseIds = hitEntities(*baseAccel, cameraRays(base, width, height), &baseHits);
  for (const CsgSweepCase &c : kCsgCases) {
    Scene scene = csgScene(c.offset, c.scale);
    auto accel = makeAccelerator(GetParam(), scene);
    std::vector<Hit> hits;
    std::vector<int> ids = hitEntities(*accel, cameraRays(scene, width, height), &hits);
    size_t differ = 0;
    for (size_t i = 0; i < ids.size(); ++i)
      differ += ids[i] != baseIds[i] || (ids[i] >= 0 && hits[i].primitive != baseHits[i].primitive);
    // Pixels on a silhouette may flip with the rounding of the placement.
    EXPECT_LE(differ, ids.size() / 200) << "offset " << c.offset << " scale " << c.scale;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, StressCsg, ::testing::ValuesIn(kBothBackends), backendParamName);

} // namespace
} // namespace lray::stress
