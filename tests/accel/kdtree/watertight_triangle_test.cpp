// Tests for src/accel/kdtree/watertight_triangle.h.
#include "accel/kdtree/watertight_triangle.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

TEST(WatertightTriangle, HitGivesDistanceAndBarycentrics) {
  Ray ray{{0.2, 0.3, -1}, {0, 0, 2}};
  TriangleHitParams p;
  ASSERT_TRUE(intersectTriangle(WatertightRay(ray), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, p));
  EXPECT_DOUBLE_EQ(p.t, 0.5); // t in units of |d|
  EXPECT_DOUBLE_EQ(p.b1, 0.2);
  EXPECT_DOUBLE_EQ(p.b2, 0.3);
  // Both facings.
  ASSERT_TRUE(intersectTriangle(WatertightRay(ray), {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, 10, p));
  EXPECT_DOUBLE_EQ(p.b1, 0.3);
}

TEST(WatertightTriangle, RespectsInterval) {
  Ray ray{{0.2, 0.3, -1}, {0, 0, 1}};
  TriangleHitParams p;
  EXPECT_FALSE(intersectTriangle(WatertightRay(ray), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1.0, p));
  ray.tMin = 1.0;
  EXPECT_FALSE(intersectTriangle(WatertightRay(ray), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5, p));
  ray.tMin = 0.5;
  EXPECT_TRUE(intersectTriangle(WatertightRay(ray), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5, p));
}

TEST(WatertightTriangle, MissesOutsideAndEdgeOn) {
  TriangleHitParams p;
  Ray outside{{0.6, 0.6, -1}, {0, 0, 1}};
  EXPECT_FALSE(intersectTriangle(WatertightRay(outside), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, p));
  Ray edgeOn{{-1, 0.2, 0}, {1, 0, 0}};
  EXPECT_FALSE(intersectTriangle(WatertightRay(edgeOn), {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, p));
}

TEST(WatertightTriangle, SharedEdgeIsHitByAtLeastOneNeighbour) {
  // Two triangles sharing the diagonal of the unit square; rays along it.
  Vec3 a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
  for (int i = 1; i < 1000; ++i) {
    double s = i / 1000.0;
    Vec3 origin{s + 0.01 * (i % 7 - 3), s + 0.013 * (i % 5 - 2), -1};
    Ray ray{origin, Vec3(s, s, 0) - origin};
    TriangleHitParams p;
    bool h1 = intersectTriangle(WatertightRay(ray), a, b, c, 10, p);
    bool h2 = intersectTriangle(WatertightRay(ray), a, c, d, 10, p);
    EXPECT_TRUE(h1 || h2) << i;
  }
}

} // namespace
} // namespace lray
