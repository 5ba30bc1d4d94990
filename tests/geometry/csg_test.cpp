// CSG (geometry/csg_ray.h): each operator on rays whose answer is known in
// closed form, rays starting inside, normals of carved surfaces, Union's
// inner surfaces against Merge, half-spaces, coincident faces, bounds.
#include "geometry/csg_ray.h"

#include "render/backends.h"

#include "csg_test_trees.h"
#include "math/spawn.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace lray {
namespace {

using test::csgEntity;
using test::leafSpec;
using test::opSpec;

constexpr double kInf = std::numeric_limits<double>::infinity();

Ray ray(const Vec3 &o, const Vec3 &d, double tMin = 0, double tMax = kInf) {
  return {o, d, tMin, tMax};
}

bool hitOf(const Entity &e, const Ray &r, Hit &h) { return intersectShape(e, 7, r, h); }

TEST(Csg, DifferenceCarvesAHoleWhoseSurfaceFacesIntoIt) {
  // A 2-unit cube minus a cylinder of radius 0.5 along z through it.
  Entity e = csgEntity(opSpec(
      CsgOp::Difference,
      {leafSpec(ShapeKind::Cube, Transform::scale(2, 2, 2)),
       leafSpec(ShapeKind::Cylinder, Transform::rotate({1, 0, 0}, 90) *
                                         Transform::scale(0.5, 4, 0.5) *
                                         Transform::translate({0, -0.5, 0}))}));
  Hit h;
  // Straight through the hole: nothing.
  EXPECT_FALSE(hitOf(e, ray({0.1, 0.1, -5}, {0, 0, 1}), h));
  EXPECT_FALSE(occludedShape(e, ray({0.1, 0.1, -5}, {0, 0, 1})));
  // Beside it: the cube's face.
  ASSERT_TRUE(hitOf(e, ray({0.8, 0.1, -5}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 4, 1e-12);
  EXPECT_NEAR(h.ng.z, -1, 1e-12);
  EXPECT_EQ(h.entity, 7u);
  EXPECT_EQ(h.primitive, 0u);
  // From inside the hole sideways: the carved wall at x = 0.5, its normal
  // pointing back into the hole (-x), reported as the cylinder (leaf 1).
  ASSERT_TRUE(hitOf(e, ray({0, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 0.5, 1e-12);
  EXPECT_NEAR(h.ng.x, -1, 1e-12);
  EXPECT_EQ(h.primitive, 1u);
  EXPECT_TRUE(occludedShape(e, ray({0, 0, 0}, {1, 0, 0})));
  EXPECT_FALSE(occludedShape(e, ray({0, 0, 0}, {1, 0, 0}, 0, 0.49)));
  // Bounds: the cube's.
  Bounds3 b = shapeWorldBounds(e);
  EXPECT_NEAR(b.lo.x, -1, 1e-9);
  EXPECT_NEAR(b.hi.z, 1, 1e-9);
  EXPECT_TRUE(shapeBounded(e));
}

TEST(Csg, IntersectionLensFromOutsideAndFromInside) {
  // Two unit spheres at x = -0.5 and 0.5: the lens is |x| <= 0.5 on the axis.
  Entity e = csgEntity(opSpec(CsgOp::Intersection,
                              {leafSpec(ShapeKind::Sphere, Transform::translate({-0.5, 0, 0})),
                               leafSpec(ShapeKind::Sphere, Transform::translate({0.5, 0, 0}))}));
  Hit h;
  ASSERT_TRUE(hitOf(e, ray({-5, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 4.5, 1e-12); // the right sphere's surface at x = -0.5
  EXPECT_EQ(h.primitive, 1u);
  EXPECT_NEAR(h.ng.x, -1, 1e-12);
  // A ray refracted into the lens: starts inside, leaves at x = 0.5
  // through the left sphere's surface, normal along the ray (outward).
  ASSERT_TRUE(hitOf(e, ray({0, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 0.5, 1e-12);
  EXPECT_EQ(h.primitive, 0u);
  EXPECT_NEAR(h.ng.x, 1, 1e-12);
  // Missing the lens but hitting both spheres' union: nothing.
  EXPECT_FALSE(hitOf(e, ray({-5, 0.95, 0}, {1, 0, 0}), h));
  // Bounds: the intersection of the spheres' boxes.
  Bounds3 b = shapeWorldBounds(e);
  EXPECT_NEAR(b.lo.x, -0.5, 1e-9);
  EXPECT_NEAR(b.hi.x, 0.5, 1e-9);
}

TEST(Csg, UnionKeepsInnerSurfacesAndMergeRemovesThem) {
  std::vector<test::CsgSpec> two = {leafSpec(ShapeKind::Sphere, Transform::translate({-0.5, 0, 0})),
                                    leafSpec(ShapeKind::Sphere, Transform::translate({0.5, 0, 0}))};
  // The Union is tested under an Intersection with a big cube (a top-level
  // Union is flattened into plain entities by the converter).
  Entity unionE = csgEntity(opSpec(
      CsgOp::Intersection,
      {opSpec(CsgOp::Union, two), leafSpec(ShapeKind::Cube, Transform::scale(10, 10, 10))}));
  Entity mergeE = csgEntity(opSpec(
      CsgOp::Intersection,
      {opSpec(CsgOp::Merge, two), leafSpec(ShapeKind::Cube, Transform::scale(10, 10, 10))}));
  Hit h;
  // From the centre along +x: the Union shows the left sphere's far side at
  // x = 0.5 (inside the right sphere); the Merge only the right one's at 1.5.
  ASSERT_TRUE(hitOf(unionE, ray({0, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 0.5, 1e-12);
  EXPECT_EQ(h.primitive, 0u);
  ASSERT_TRUE(hitOf(mergeE, ray({0, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 1.5, 1e-12);
  EXPECT_EQ(h.primitive, 1u);
  // From outside both show the same outer surface.
  ASSERT_TRUE(hitOf(unionE, ray({-5, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 3.5, 1e-12);
  ASSERT_TRUE(hitOf(mergeE, ray({-5, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 3.5, 1e-12);
}

TEST(Csg, PlaneIsAHalfSpaceThatClips) {
  // A unit sphere cut by the plane y = 0.25 (solid below).
  Entity e = csgEntity(opSpec(CsgOp::Intersection,
                              {leafSpec(ShapeKind::Sphere, Transform()),
                               leafSpec(ShapeKind::Plane, Transform::translate({0, 0.25, 0}))}));
  Hit h;
  ASSERT_TRUE(hitOf(e, ray({0, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 4.75, 1e-12);
  EXPECT_NEAR(h.ng.y, 1, 1e-12);
  EXPECT_EQ(h.primitive, 1u);
  ASSERT_TRUE(hitOf(e, ray({0, -5, 0}, {0, 1, 0}), h));
  EXPECT_NEAR(h.t, 4, 1e-12);
  EXPECT_TRUE(shapeBounded(e)); // the sphere's box bounds it
  // A Plane minus a sphere: unbounded, a bowl-shaped dent.
  Entity dent = csgEntity(opSpec(CsgOp::Difference, {leafSpec(ShapeKind::Plane, Transform()),
                                                     leafSpec(ShapeKind::Sphere, Transform())}));
  EXPECT_FALSE(shapeBounded(dent));
  ASSERT_TRUE(hitOf(dent, ray({0, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 6, 1e-12); // the bottom of the dent, y = -1
  EXPECT_NEAR(h.ng.y, 1, 1e-12);
  ASSERT_TRUE(hitOf(dent, ray({3, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 5, 1e-12);
}

TEST(Csg, DifferenceOfDifferencesAndTorusAndCone) {
  // A torus minus a cube that removes its +x half: a ray along the axis
  // at x = 1 (through the tube) sees nothing; at x = -1 the tube.
  Torus t;
  Entity e = csgEntity(opSpec(
      CsgOp::Difference,
      {leafSpec(ShapeKind::Torus, Transform()),
       leafSpec(ShapeKind::Cube, Transform::translate({1.5, 0, 0}) * Transform::scale(3, 3, 3))}));
  Hit h;
  EXPECT_FALSE(hitOf(e, ray({1, 5, 0}, {0, -1, 0}), h));
  ASSERT_TRUE(hitOf(e, ray({-1, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 5 - t.minor, 1e-9);
  // Along x: the tube's outer equator at x = -1.25.
  ASSERT_TRUE(hitOf(e, ray({-5, 0, 0}, {1, 0, 0}), h));
  EXPECT_NEAR(h.t, 5 - 1.25, 1e-9);
  // A cone minus a smaller cone: a shell; from the apex side down the axis
  // the ray enters the outer cone's apex region then the hollow.
  Entity shell = csgEntity(
      opSpec(CsgOp::Difference, {leafSpec(ShapeKind::Cone, Transform()),
                                 leafSpec(ShapeKind::Cone, Transform::translate({0, -0.1, 0}) *
                                                               Transform::scale(0.8, 1, 0.8))}));
  ASSERT_TRUE(hitOf(shell, ray({0.3, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 5 - 0.7, 1e-9); // outer side at y = 1 - 0.3
  Hit h2;
  ASSERT_TRUE(hitOf(shell, ray(h.p, {0, -1, 0}, 1e-9), h2)); // then the inner surface
  EXPECT_NEAR(h2.p.y, 0.9 - 0.3 / 0.8, 1e-9);
  // Out of the shell's material into the hollow: the inner cone's outward
  // normal (up and out) reversed, along the ray leaving the material.
  EXPECT_LT(h2.ng.y, 0);
  EXPECT_LT(h2.ng.x, 0);
}

// Coincident faces: a cube minus a box sharing its -z face, placed by
// random rotations composed differently for the two leaves (so their t's
// differ in the last bits): every ray along the stack hits the carved
// face, never a speckle of the shared face; and two stacked cubes merged
// show no face between them.
TEST(Csg, CoincidentFacesGiveOneAnswer) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Transform rot = Transform::rotate({u(rng), u(rng), u(rng) + 2}, 180 * u(rng)) *
                          Transform::scale(1.7, 1.7, 1.7);
    Entity diff = csgEntity(opSpec(CsgOp::Difference,
                                   {leafSpec(ShapeKind::Cube, Transform()),
                                    leafSpec(ShapeKind::Cube, Transform::translate({0, 0, -0.25}) *
                                                                  Transform::scale(1, 1, 0.5))},
                                   rot));
    Entity merged = csgEntity(opSpec(CsgOp::Merge,
                                     {leafSpec(ShapeKind::Cube, Transform()),
                                      leafSpec(ShapeKind::Cube, Transform::translate({0, 0, 1}))},
                                     rot));
    const Vec3 axis = rot.applyVector({0, 0, 1});
    for (int i = 0; i < 500; ++i) {
      const Vec3 start = rot.applyPoint({0.45 * u(rng), 0.45 * u(rng), -3});
      Hit h;
      ASSERT_TRUE(hitOf(diff, ray(start, axis), h));
      EXPECT_NEAR(h.t, 3, 1e-9) << "trial " << trial << " ray " << i;
      EXPECT_EQ(h.primitive, 1u);
      ASSERT_TRUE(hitOf(merged, ray(start, axis), h));
      EXPECT_NEAR(h.t, 2.5, 1e-9);
      // From inside the lower cube, the next surface is the top of the upper.
      ASSERT_TRUE(hitOf(merged, ray(rot.applyPoint({0.45 * u(rng), 0.45 * u(rng), 0}), axis), h));
      EXPECT_NEAR(h.t, 1.5, 1e-9);
    }
  }
}

// An Intersection of disjoint solids has empty bounds and nothing to hit,
// on both backends (Embree must not get an inverted box).
TEST(Csg, AnEmptyResultIsNeverHitOnEitherBackend) {
  Scene s;
  s.entities.push_back(csgEntity(
      opSpec(CsgOp::Intersection, {leafSpec(ShapeKind::Sphere, Transform::translate({-3, 0, 5})),
                                   leafSpec(ShapeKind::Sphere, Transform::translate({3, 0, 5}))})));
  s.entities.push_back(test::leafSpec(ShapeKind::Sphere, Transform::translate({0, 0, 9})).leaf);
  s.textures.push_back({});
  EXPECT_TRUE(shapeWorldBounds(s.entities[0]).empty());
  for (BackendKind kind : {BackendKind::Embree, BackendKind::KdTree}) {
    auto accel = makeAccelerator(kind, s);
    for (double x : {-3.0, 0.0, 3.0}) {
      Hit h;
      const Ray r{{x, 0, 0}, {0, 0, 1}, 0, kInf};
      const bool hit = accel->intersect(r, h);
      EXPECT_EQ(hit, x == 0.0) << backendName(kind) << " x " << x;
      if (hit) {
        EXPECT_EQ(h.entity, 1u);
      }
    }
  }
}

// Secondary rays from every kind of CSG surface do not find it again.
TEST(Csg, SpawnedRaysLeaveTheSurface) {
  Entity e = csgEntity(opSpec(
      CsgOp::Difference,
      {opSpec(CsgOp::Intersection, {leafSpec(ShapeKind::Cube, Transform::scale(2, 2, 2)),
                                    leafSpec(ShapeKind::Sphere, Transform::scale(1.3, 1.3, 1.3))}),
       leafSpec(ShapeKind::Cylinder,
                Transform::translate({0, -2, 0}) * Transform::scale(0.5, 4, 0.5))}));
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 o{4 * u(rng), 4 * u(rng), 4 * u(rng)};
    Vec3 d = Vec3{0.8 * u(rng), 0.8 * u(rng), 0.8 * u(rng)} - o;
    Hit h;
    if (!hitOf(e, ray(o, d), h)) continue;
    ++hits;
    // Leaving on the side the ray came from, and going through.
    Ray back = spawnRay(h, -d);
    Hit again;
    if (hitOf(e, back, again)) {
      EXPECT_GT(again.t * length(d), 1e-6) << i;
    }
    Ray through = spawnRay(h, d);
    if (hitOf(e, through, again)) {
      EXPECT_GT(again.t * length(d), 1e-6) << i;
    }
  }
  EXPECT_GT(hits, 5000);
}

} // namespace
} // namespace lray
