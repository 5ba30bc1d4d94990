// Tests for src/geometry/shape: known hits, misses, normals and uvs of the
// analytic shapes (lua/README.md, "Entities"), rays from inside, caps, apex, edges, bounds.
#include "geometry/shape.h"
#include "shape_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace lray {
namespace {

Entity makeEntity(ShapeKind kind, const Transform &xf = Transform(), bool open = false) {
  Entity e;
  e.shape = makeShape(kind);
  e.worldFromObject = xf;
  setOpen(e, open);
  return e;
}

void expectVecNear(const Vec3 &a, const Vec3 &b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Ray ray(const Vec3 &o, const Vec3 &d) { return {o, d}; }

TEST(Sphere, HitFromOutsideAlongZ) {
  Entity e = makeEntity(ShapeKind::Sphere);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 7, ray({0, 0, -5}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 4, 1e-14);
  EXPECT_EQ(h.entity, 7u);
  EXPECT_EQ(h.primitive, 0u);
  expectVecNear(h.p, {0, 0, -1});
  expectVecNear(h.ng, {0, 0, -1});
  expectVecNear(h.ns, {0, 0, -1});
  // atan2(-1, 0) = -pi/2: u = (pi/2) / (2 pi) = 0.25; v = (0 + 1) / 2.
  EXPECT_NEAR(h.u, 0.25, 1e-14);
  EXPECT_NEAR(h.v, 0.5, 1e-14);
  EXPECT_GT(h.pError, 0);
  EXPECT_LT(h.pError, 1e-12);
}

TEST(Sphere, UvAtKnownPoints) {
  Entity e = makeEntity(ShapeKind::Sphere);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({5, 0, 0}, {-1, 0, 0}), h)); // +x: atan2(0,1) = 0
  EXPECT_NEAR(h.u, 0.5, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 5, 0}, {0, -1, 0}), h)); // top
  EXPECT_NEAR(h.v, 1, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0, 5}, {0, 0, -1}), h)); // +z: atan2(1,0) = pi/2
  EXPECT_NEAR(h.u, 0.75, 1e-14);
}

TEST(Sphere, RayFromInsideHitsFarSide) {
  Entity e = makeEntity(ShapeKind::Sphere);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0, 0}, {0, 2, 0}), h));
  EXPECT_NEAR(h.t, 0.5, 1e-14); // t in units of |d|
  expectVecNear(h.ng, {0, 1, 0}); // outward, not flipped
}

TEST(Sphere, MissesAndRange) {
  Entity e = makeEntity(ShapeKind::Sphere);
  Hit h;
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 1.0001, -5}, {0, 0, 1}), h));
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 0, 5}, {0, 0, 1}), h)); // behind
  Ray r = ray({0, 0, -5}, {0, 0, 1});
  r.tMax = 3.9;
  EXPECT_FALSE(intersectShape(e, 0, r, h));
  EXPECT_FALSE(occludedShape(e, r));
  r.tMax = 4.1;
  EXPECT_TRUE(occludedShape(e, r));
}

TEST(Sphere, GrazingRayTouchesOrMissesWithoutNaN) {
  Entity e = makeEntity(ShapeKind::Sphere);
  Hit h;
  if (intersectShape(e, 0, ray({1, 0, -5}, {0, 0, 1}), h)) {
    EXPECT_NEAR(h.t, 5, 1e-6);
    EXPECT_TRUE(isFinite(h.ng));
  }
  EXPECT_FALSE(intersectShape(e, 0, ray({1 + 1e-12, 0, -5}, {0, 0, 1}), h));
}

TEST(Sphere, TransformedNormalUsesInverseTranspose) {
  // Ellipsoid with semi-axes 2, 1, 1; at the point (sqrt2, sqrt(1/2), 0)
  // the outward normal is proportional to (x/4, y, 0).
  Entity e = makeEntity(ShapeKind::Sphere, Transform::scale(2, 1, 1));
  Hit h;
  double x = std::sqrt(2.0), y = std::sqrt(0.5);
  Vec3 n = normalize(Vec3(x / 4, y, 0));
  ASSERT_TRUE(intersectShape(e, 0, ray(Vec3(x, y, 0) + n * 5, -n), h));
  EXPECT_NEAR(h.t, 5, 1e-9);
  expectVecNear(h.p, {x, y, 0}, 1e-9);
  expectVecNear(h.ng, normalize(Vec3(x / 4, y, 0)), 1e-9);
  expectVecNear(h.pObject, {x / 2, y, 0}, 1e-9);
}

// Sphere::intersect settles rays that start outside and move away before
// its roots: the answer must be the roots' own, for rays leaving the
// surface within a few ulps (shadow rays from its points), grazing ones
// and ones from far away; a negative tMin takes the roots behind.
TEST(Sphere, OutwardRaysMissAsTheRootsSay) {
  const Sphere sphere;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  int settled = 0;
  for (int i = 0; i < 200000; ++i) {
    Vec3 p(u(rng), u(rng), u(rng));
    if (length(p) == 0) continue;
    const double scale = i % 3 == 0 ? 1 + std::ldexp(u(rng), -40) : 1 + std::fabs(u(rng)) * 1e3;
    const Vec3 o = p / length(p) * scale;
    Vec3 d(u(rng), u(rng), u(rng));
    if (i % 5 == 0) d = d - o * (dot(d, o) / dot(o, o)); // about tangent
    const double tMin = i % 11 == 0 ? -2e3 : (i % 7 == 0 ? 0.5 : 0.0); // -2e3: behind counts
    const Ray r{o, d, tMin, i % 2 == 0 ? 1.0 : 1e30};
    double t0, t1;
    bool expected = sphere_detail::roots(r, t0, t1) && (inOpenRange(r, t0) || inOpenRange(r, t1));
    ObjectHit hit;
    EXPECT_EQ(sphere.intersect(r, hit), expected) << i;
    settled += dot(o, d) > 0 && dot(o, o) - 1 > 0;
  }
  EXPECT_GT(settled, 50000);
}

// Sphere::missesLine settles lines before the origin shift: wherever it
// does, the full test (shift, then intersect) must miss too, for lines
// from near and from up to 1e10 away (the shift's rounding grows with the
// distance), passing just outside its margin, at every tMin and tMax. And
// it must settle most clear misses, or it only costs.
TEST(Sphere, LinesMissedBeforeTheShiftMissAfterIt) {
  const Sphere sphere;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int settled = 0, clearMisses = 0;
  for (int i = 0; i < 300000; ++i) {
    const Vec3 dir = normalize(Vec3(u(rng), u(rng), u(rng)) + Vec3(0, 1e-9, 0));
    Vec3 side = cross(dir, Vec3(u(rng), u(rng), u(rng)));
    if (length(side) == 0) continue;
    side = normalize(side);
    // The line's distance from the centre: around the margin, or anywhere.
    const double dist = i % 2 == 0 ? std::sqrt(1 + 1e-3) * (1 + std::ldexp(u(rng), -12))
                                   : 3 * std::fabs(u(rng));
    const double far = std::ldexp(1.0, static_cast<int>(rng() % 34)); // 1 to 2^33
    const Vec3 o = side * dist - dir * (far * u(rng));
    const Vec3 d = dir * std::ldexp(1.0 + std::fabs(u(rng)), static_cast<int>(rng() % 9) - 4);
    const double tMin = i % 3 == 0 ? -1e12 : 0.0;
    Ray r{o, d, tMin, i % 4 == 0 ? 1.0 : 1e30};
    const bool missed = sphere.missesLine(r);
    settled += missed;
    clearMisses += dist > 1.01;
    const double shift = sphere.originShift(r);
    if (shift != 0) {
      r.o = r.at(shift);
      r.tMin -= shift;
      r.tMax -= shift;
    }
    ObjectHit hit;
    if (missed) {
      ASSERT_FALSE(sphere.intersect(r, hit)) << i;
    }
  }
  EXPECT_GT(settled, clearMisses * 9 / 10);
}

TEST(Sphere, WorldBoundsAreExactForRotatedEllipsoid) {
  Transform xf = Transform::translate({1, 2, 3}) * Transform::rotate({0, 0, 1}, 30) *
                 Transform::scale(3, 1, 2);
  Bounds3 b = shapeWorldBounds(makeEntity(ShapeKind::Sphere, xf));
  // x extent: sqrt((3 cos30)^2 + (sin30)^2), y: sqrt((3 sin30)^2 + cos30^2), z: 2.
  double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  double ex = std::hypot(3 * c, s), ey = std::hypot(3 * s, c);
  EXPECT_NEAR(b.lo.x, 1 - ex, 1e-12);
  EXPECT_NEAR(b.hi.x, 1 + ex, 1e-12);
  EXPECT_NEAR(b.lo.y, 2 - ey, 1e-12);
  EXPECT_NEAR(b.hi.y, 2 + ey, 1e-12);
  EXPECT_NEAR(b.lo.z, 1, 1e-12);
  EXPECT_NEAR(b.hi.z, 5, 1e-12);
}

TEST(Cylinder, SideCapsAndUv) {
  Entity e = makeEntity(ShapeKind::Cylinder);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({5, 0.25, 0}, {-1, 0, 0}), h));
  EXPECT_NEAR(h.t, 4, 1e-14);
  expectVecNear(h.ng, {1, 0, 0});
  EXPECT_NEAR(h.u, 0, 1e-14);
  EXPECT_NEAR(h.v, 0.25, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0.5, 5}, {0, 0, -1}), h)); // +z: a quarter turn
  EXPECT_NEAR(h.u, 0.25, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0.5, -5}, {0, 0, 1}), h)); // -z: three quarters
  EXPECT_NEAR(h.u, 0.75, 1e-14);
  // Top cap from above, bottom cap from below.
  ASSERT_TRUE(intersectShape(e, 0, ray({0.5, 3, -0.5}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 2, 1e-14);
  expectVecNear(h.ng, {0, 1, 0});
  EXPECT_NEAR(h.u, 0.75, 1e-14);
  EXPECT_NEAR(h.v, 0.25, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, -2, 0}, {0, 1, 0}), h));
  EXPECT_NEAR(h.t, 2, 1e-14);
  expectVecNear(h.ng, {0, -1, 0});
}

TEST(Cylinder, RayAlongAxis) {
  Entity e = makeEntity(ShapeKind::Cylinder);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({0, -1, 0}, {0, 1, 0}), h));
  EXPECT_NEAR(h.t, 1, 1e-14);
  // Along the axis of an open cylinder: no hit, and no NaN trouble.
  Entity open = makeEntity(ShapeKind::Cylinder, Transform(), true);
  EXPECT_FALSE(intersectShape(open, 0, ray({0, -1, 0}, {0, 1, 0}), h));
  // Exactly on the side surface, along it: treated as a miss or a hit, never NaN.
  if (intersectShape(open, 0, ray({1, -1, 0}, {0, 1, 0}), h)) {
    EXPECT_TRUE(isFinite(h.p));
  }
}

TEST(Cylinder, FromInsideAndOpen) {
  Entity e = makeEntity(ShapeKind::Cylinder);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0.5, 0}, {0, 1, 0}), h)); // inside, up: top cap
  EXPECT_NEAR(h.t, 0.5, 1e-14);
  expectVecNear(h.ng, {0, 1, 0});
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0.5, 0}, {1, 0, 0}), h)); // inside, sideways
  EXPECT_NEAR(h.t, 1, 1e-14);
  Entity open = makeEntity(ShapeKind::Cylinder, Transform(), true);
  // Through the open top: hits the inside of the far wall.
  ASSERT_TRUE(intersectShape(open, 0, ray({0, 2, 0}, {0.5, -1, 0}), h));
  EXPECT_NEAR(h.p.x, 1, 1e-12);
  EXPECT_NEAR(h.p.y, 0, 1e-12);
  expectVecNear(h.ng, {1, 0, 0}); // outward, although the ray hits the inside
  EXPECT_FALSE(intersectShape(open, 0, ray({0, 2, 0}, {0, -1, 0}), h));
}

TEST(Cylinder, WorldBoundsTight) {
  Transform xf = Transform::rotate({0, 0, 1}, 90); // axis along -x
  Bounds3 b = shapeWorldBounds(makeEntity(ShapeKind::Cylinder, xf));
  expectVecNear(b.lo, {-1, -1, -1});
  expectVecNear(b.hi, {0, 1, 1});
}

TEST(Cone, SideBaseAndApex) {
  Entity e = makeEntity(ShapeKind::Cone);
  Hit h;
  // At y = 0.5 the radius is 0.5.
  ASSERT_TRUE(intersectShape(e, 0, ray({5, 0.5, 0}, {-1, 0, 0}), h));
  EXPECT_NEAR(h.t, 4.5, 1e-14);
  expectVecNear(h.ng, normalize(Vec3(1, 1, 0)));
  EXPECT_NEAR(h.u, 0, 1e-14);
  EXPECT_NEAR(h.v, 0.5, 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0.25, -1, 0.5}, {0, 1, 0}), h)); // base
  EXPECT_NEAR(h.t, 1, 1e-14);
  expectVecNear(h.ng, {0, -1, 0});
  EXPECT_NEAR(h.u, 0.625, 1e-14);
  EXPECT_NEAR(h.v, 0.75, 1e-14);
  // Straight down onto the apex.
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 3, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 2, 1e-12);
  EXPECT_TRUE(isFinite(h.ng));
  EXPECT_GT(h.ng.y, 0);
  // Into the cone through the apex at an angle, from inside the other nappe.
  ASSERT_TRUE(intersectShape(e, 0, ray({-0.5, 2, -0.2}, {0.5, -1, 0.2}), h));
  EXPECT_NEAR(h.t, 1, 1e-9);
  EXPECT_TRUE(isFinite(h.ng));
  // Above the apex, missing the real cone but crossing the upper nappe.
  EXPECT_FALSE(intersectShape(e, 0, ray({-5, 2, 0}, {1, 0, 0}), h));
}

TEST(Cone, ParallelToGeneratorAndOpen) {
  Entity e = makeEntity(ShapeKind::Cone);
  Hit h;
  // Direction (1, -1, 0) is parallel to the generator in the xy plane.
  ASSERT_TRUE(intersectShape(e, 0, ray({-2, 1, 0}, {1, -1, 0}), h));
  EXPECT_TRUE(isFinite(h.p));
  Entity open = makeEntity(ShapeKind::Cone, Transform(), true);
  EXPECT_FALSE(intersectShape(open, 0, ray({0.25, -1, 0}, {0, 1, 0}), h) && h.p.y < 0.5);
  ASSERT_TRUE(intersectShape(open, 0, ray({0.25, -1, 0}, {0, 1, 0}), h)); // inside of the side
  EXPECT_NEAR(h.p.y, 0.75, 1e-12);
}

TEST(Cone, WorldBounds) {
  Bounds3 b = shapeWorldBounds(makeEntity(ShapeKind::Cone, Transform::translate({0, 1, 0})));
  expectVecNear(b.lo, {-1, 1, -1});
  expectVecNear(b.hi, {1, 2, 1});
}

TEST(Cube, FacesNormalsAndUv) {
  Entity e = makeEntity(ShapeKind::Cube);
  struct Case {
    Vec3 o, d, n;
    double u, v;
  };
  // Points (0.25, 0.1, ...) etc. on each face; uv per the table in cube.cpp.
  const Case cases[] = {
      {{0.25, 0.1, -5}, {0, 0, 1}, {0, 0, -1}, 0.75, 0.6},
      {{0.25, 0.1, 5}, {0, 0, -1}, {0, 0, 1}, 0.25, 0.6},
      {{5, 0.1, 0.25}, {-1, 0, 0}, {1, 0, 0}, 0.75, 0.6},
      {{-5, 0.1, 0.25}, {1, 0, 0}, {-1, 0, 0}, 0.25, 0.6},
      {{0.25, 5, 0.1}, {0, -1, 0}, {0, 1, 0}, 0.75, 0.6},
      {{0.25, -5, 0.1}, {0, 1, 0}, {0, -1, 0}, 0.25, 0.6},
  };
  for (const Case &c : cases) {
    Hit h;
    ASSERT_TRUE(intersectShape(e, 0, ray(c.o, c.d), h));
    EXPECT_NEAR(h.t, 4.5, 1e-14);
    expectVecNear(h.ng, c.n);
    EXPECT_NEAR(h.u, c.u, 1e-14);
    EXPECT_NEAR(h.v, c.v, 1e-14);
  }
}

TEST(Cube, FaceCornersSpanUnitSquare) {
  Entity e = makeEntity(ShapeKind::Cube);
  Hit h;
  double umin = 1, umax = 0, vmin = 1, vmax = 0;
  for (double x : {-0.4999, 0.4999})
    for (double y : {-0.4999, 0.4999}) {
      ASSERT_TRUE(intersectShape(e, 0, ray({x, y, -3}, {0, 0, 1}), h));
      umin = std::min(umin, h.u), umax = std::max(umax, h.u);
      vmin = std::min(vmin, h.v), vmax = std::max(vmax, h.v);
    }
  EXPECT_NEAR(umin, 0, 1e-3);
  EXPECT_NEAR(umax, 1, 1e-3);
  EXPECT_NEAR(vmin, 0, 1e-3);
  EXPECT_NEAR(vmax, 1, 1e-3);
}

TEST(Cube, InsideAlongEdgesAndCorners) {
  Entity e = makeEntity(ShapeKind::Cube);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0, 0}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 0.5, 1e-14);
  expectVecNear(h.ng, {0, 0, 1});
  // Along an edge (x = z = 0.5): reaches the bottom face's corner.
  ASSERT_TRUE(intersectShape(e, 0, ray({0.5, -3, 0.5}, {0, 1, 0}), h));
  EXPECT_NEAR(h.t, 2.5, 1e-14);
  EXPECT_TRUE(isFinite(h.ng));
  // Through a corner diagonally.
  ASSERT_TRUE(intersectShape(e, 0, ray({-1.5, -1.5, -1.5}, {1, 1, 1}), h));
  EXPECT_NEAR(h.t, 1, 1e-14);
  EXPECT_TRUE(isFinite(h.ng));
  EXPECT_GE(h.u, 0);
  EXPECT_LE(h.u, 1);
  // Parallel to a face, outside the slab.
  EXPECT_FALSE(intersectShape(e, 0, ray({0.6, -3, 0}, {0, 1, 0}), h));
}

TEST(Cube, WorldBoundsOfRotatedCube) {
  Bounds3 b = shapeWorldBounds(makeEntity(ShapeKind::Cube, Transform::rotate({0, 1, 0}, 45)));
  double r = std::sqrt(0.5);
  expectVecNear(b.lo, {-r, -0.5, -r});
  expectVecNear(b.hi, {r, 0.5, r});
}

// --- Plane -------------------------------------------------------------------

TEST(Plane, HitFromAboveAndBelowWithLocalXzAsUv) {
  Entity e = makeEntity(ShapeKind::Plane);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 2, ray({0.3, 2, -0.4}, {0, -1, 0}), h));
  EXPECT_EQ(h.t, 2);
  EXPECT_EQ(h.entity, 2u);
  expectVecNear(h.p, {0.3, 0, -0.4}, 0);
  expectVecNear(h.ng, {0, 1, 0}, 0);
  expectVecNear(h.ns, {0, 1, 0}, 0);
  EXPECT_EQ(h.u, 0.3);
  EXPECT_EQ(h.v, -0.4);
  // From below: the same outward normal (+y); the integrator flips it.
  ASSERT_TRUE(intersectShape(e, 2, ray({5, -3, 7}, {1, 3, 0}), h));
  EXPECT_EQ(h.t, 1);
  expectVecNear(h.p, {6, 0, 7});
  expectVecNear(h.ng, {0, 1, 0}, 0);
  EXPECT_EQ(h.u, 6);
  EXPECT_EQ(h.v, 7);
}

TEST(Plane, ParallelAndRecedingRaysMiss) {
  Entity e = makeEntity(ShapeKind::Plane);
  Hit h;
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 1, 0}, {1, 0, 0}), h));
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 0, 0}, {1, 0, 1}), h)); // lies in it
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 1, 0}, {0, 1, 0}), h));
  EXPECT_FALSE(occludedShape(e, ray({0, 1, 0}, {0.3, 1, 0})));
  Ray shadow = ray({0, 1, 0}, {0, -2, 0});
  shadow.tMax = 0.4; // stops short of the plane
  EXPECT_FALSE(occludedShape(e, shadow));
  shadow.tMax = 0.6;
  EXPECT_TRUE(occludedShape(e, shadow));
}

TEST(Plane, TransformMovesItAndItsNormalAndUv) {
  // Rotate(x, 90) maps +y to +z: the plane z = 3 facing +z, local x = world x,
  // local z = -world y.
  Entity e = makeEntity(ShapeKind::Plane,
                        Transform::translate({0, 0, 3}) * Transform::rotate({1, 0, 0}, 90));
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({1, 2, -1}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 4, 1e-14);
  expectVecNear(h.p, {1, 2, 3}, 1e-14);
  expectVecNear(h.ng, {0, 0, 1}, 1e-15);
  EXPECT_NEAR(h.u, 1, 1e-14);
  EXPECT_NEAR(h.v, -2, 1e-14);
  EXPECT_GT(h.pError, 0);
  EXPECT_LT(h.pError, 1e-12);
}

TEST(Plane, IsUnboundedSoTheTreesLeaveItOut) {
  Entity e = makeEntity(ShapeKind::Plane, Transform::translate({0, -1, 0}));
  EXPECT_FALSE(shapeBounded(e));
  EXPECT_TRUE(shapeBounded(makeEntity(ShapeKind::Sphere)));
  Bounds3 b = shapeWorldBounds(e);
  EXPECT_FALSE(std::isfinite(b.lo.x) || std::isfinite(b.hi.y));
}

TEST(Plane, DistantHitsStayOnThePlane) {
  // 1e4 away along a grazing ray: the point is snapped onto y = 0 and the
  // refined t agrees with the exact one.
  Entity e = makeEntity(ShapeKind::Plane);
  Ray r = ray({0, 1, 0}, {1e4, -1, 0.5});
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, r, h));
  EXPECT_EQ(h.p.y, 0);
  EXPECT_EQ(h.t, 1);
  EXPECT_NEAR(h.u, 1e4, 1e-9);
}

// --- Torus -------------------------------------------------------------------

Entity makeTorus(double major, double minor, const Transform &xf = Transform()) {
  Entity e = makeEntity(ShapeKind::Torus, xf);
  std::get<Torus>(e.shape) = Torus{major, minor};
  return e;
}

TEST(Torus, KnownHitsNormalsAndUv) {
  Entity e = makeTorus(1, 0.25);
  Hit h;
  // Along -x onto the outer equator at +x: u = 0, v = 0, normal +x.
  ASSERT_TRUE(intersectShape(e, 4, ray({5, 0, 0}, {-1, 0, 0}), h));
  EXPECT_NEAR(h.t, 3.75, 1e-15);
  EXPECT_EQ(h.entity, 4u);
  expectVecNear(h.p, {1.25, 0, 0}, 1e-15);
  expectVecNear(h.ng, {1, 0, 0}, 1e-15);
  EXPECT_NEAR(h.u, 0, 1e-15);
  EXPECT_NEAR(h.v, 0, 1e-15);
  // Down onto the top of the tube at +z: u = 0.25 (+z is a quarter turn
  // from +x), v = 0.25 (a quarter turn about the tube towards +y).
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 2, 1}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 1.75, 1e-15);
  expectVecNear(h.ng, {0, 1, 0}, 1e-15);
  EXPECT_NEAR(h.u, 0.25, 1e-15);
  EXPECT_NEAR(h.v, 0.25, 1e-15);
  // The inner equator at -x, seen from the centre: v = 0.5, normal +x
  // (pointing into the hole).
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0, 0}, {-1, 0, 0}), h));
  EXPECT_NEAR(h.t, 0.75, 1e-15);
  expectVecNear(h.ng, {1, 0, 0}, 1e-15);
  EXPECT_NEAR(h.u, 0.5, 1e-15);
  EXPECT_NEAR(h.v, 0.5, 1e-15);
}

TEST(Torus, ThroughTheHoleAndAcrossBothTubes) {
  Entity e = makeTorus(1, 0.25);
  Hit h;
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 5, 0}, {0, -1, 0}), h)); // down the axis
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 0.3, -5}, {0, 0, 1}), h)); // just above
  // Across the ring: four roots, the nearest is taken; a ray starting inside
  // the tube finds its exit.
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0.1, -5}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 5 - 1 - std::sqrt(0.25 * 0.25 - 0.01), 1e-14);
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 0, -1}, {0, 0, 1}), h));
  EXPECT_NEAR(h.t, 0.25, 1e-15);
  expectVecNear(h.ng, {0, 0, 1}, 1e-15);
  Ray shadow = ray({0, 0, -5}, {0, 0, 1});
  shadow.tMax = 3.7; // stops before the tube
  EXPECT_FALSE(occludedShape(e, shadow));
  shadow.tMax = 3.8;
  EXPECT_TRUE(occludedShape(e, shadow));
}

TEST(Torus, ParametersTransformAndBounds) {
  // major 3, minor 1, stood up by Rotate(x, 90) (its axis along z) and moved.
  Transform xf = Transform::translate({0, 0, 10}) * Transform::rotate({1, 0, 0}, 90);
  Entity e = makeTorus(3, 1, xf);
  Hit h;
  EXPECT_FALSE(intersectShape(e, 0, ray({0, 0, 0}, {0, 0, 1}), h)); // through the 4-wide hole
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 3, 0}, {0, 0, 1}), h));  // onto the tube at y = 3
  EXPECT_NEAR(h.t, 9, 1e-13);
  expectVecNear(h.ng, {0, 0, -1}, 1e-14);
  Bounds3 b = shapeWorldBounds(e);
  expectVecNear(b.lo, {-4, -4, 9}, 1e-12);
  expectVecNear(b.hi, {4, 4, 11}, 1e-12);
}

TEST(Torus, SpindleTorusHasOneSurface) {
  // minor > major: the apple shape; the axis is inside it between
  // y = -+sqrt(r^2 - R^2) and the surface is where the distance to the
  // centre circle is r.
  Entity e = makeTorus(0.5, 1);
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, ray({0, 5, 0}, {0, -1, 0}), h));
  EXPECT_NEAR(h.t, 5 - std::sqrt(0.75), 1e-14); // a dimple point: no normal checked
  ASSERT_TRUE(intersectShape(e, 0, ray({5, 0, 0}, {-1, 0, 0}), h));
  EXPECT_NEAR(h.t, 3.5, 1e-14);
}

TEST(Plane, InWorldIsTheObjectPlanePlaced) {
  const Transform t = Transform::translate({1, 2, 3}) * Transform::rotate({1, 0, 0}, 30) *
                      Transform::scale(2, 3, 4);
  const Plane::WorldPlane p = Plane::inWorld(t);
  EXPECT_NEAR(length(p.normal), 1, 1e-12);
  // Points of the object plane lie on it; the solid side (y < 0) is below.
  for (const Vec3 &q : {Vec3(0, 0, 0), Vec3(5, 0, -2), Vec3(-1, 0, 7)})
    EXPECT_NEAR(dot(p.normal, t.applyPoint(q)), p.offset, 1e-12);
  EXPECT_LT(dot(p.normal, t.applyPoint({0.5, -1, 0.25})), p.offset);
  EXPECT_GT(dot(p.normal, t.applyPoint({0.5, 1, 0.25})), p.offset);
}

// An entity whose texture reads no (u, v) (Entity::readsUv false) gets the
// same hit without them: the same t, point and normal.
TEST(Shapes, WithoutUvTheSameHit) {
  for (ShapeKind kind :
       {ShapeKind::Sphere, ShapeKind::Cylinder, ShapeKind::Cone, ShapeKind::Torus}) {
    Entity with = makeEntity(kind, Transform::translate({0.1, 0.2, 0.3}));
    Entity without = with;
    without.readsUv = false;
    for (const Ray &r : {ray({1.0, 0.25, -5}, {0, 0, 1}), ray({5, 0.25, 0.2}, {-1, 0.01, 0})}) {
      Hit a, b;
      ASSERT_TRUE(intersectShape(with, 0, r, a)) << shapeName(with.shape);
      ASSERT_TRUE(intersectShape(without, 0, r, b)) << shapeName(with.shape);
      EXPECT_EQ(a.t, b.t);
      EXPECT_EQ(a.p, b.p);
      EXPECT_EQ(a.ng, b.ng);
      EXPECT_EQ(a.pObject, b.pObject);
      EXPECT_NE(a.u, b.u) << shapeName(with.shape); // the test could tell
    }
  }
}

} // namespace
} // namespace lray
