// Tests for src/accel/kdtree/triangle_clip.h.
#include "accel/kdtree/triangle_clip.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

TEST(ClipTriangleToBox, InsideIsUnchanged) {
  Bounds3 b = clipTriangleToBox({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, Bounds3({-1, -1, -1}, {2, 2, 2}));
  EXPECT_EQ(b.lo, Vec3(0, 0, 0));
  EXPECT_EQ(b.hi, Vec3(1, 1, 0));
}

TEST(ClipTriangleToBox, ClipsToThePartInside) {
  // The triangle's part with x >= 0.5 has y <= 0.5.
  Bounds3 b = clipTriangleToBox({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, Bounds3({0.5, -1, -1}, {2, 2, 2}));
  EXPECT_DOUBLE_EQ(b.lo.x, 0.5);
  EXPECT_DOUBLE_EQ(b.hi.x, 1);
  EXPECT_DOUBLE_EQ(b.lo.y, 0);
  EXPECT_DOUBLE_EQ(b.hi.y, 0.5);
}

TEST(ClipTriangleToBox, MissIsEmpty) {
  // Bounds overlap the box corner, the triangle does not.
  Bounds3 corner({0.8, 0.8, -1}, {2, 2, 1});
  Bounds3 b = clipTriangleToBox({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, corner);
  EXPECT_TRUE(b.empty());
}

TEST(ClipTriangleToBox, TriangleInTheBoxFaceIsKept) {
  Bounds3 b = clipTriangleToBox({0, 0, 1}, {1, 0, 1}, {0, 1, 1}, Bounds3({0, 0, 0}, {1, 1, 1}));
  EXPECT_FALSE(b.empty());
  EXPECT_EQ(b.lo.z, 1);
  EXPECT_EQ(b.hi.z, 1);
}

} // namespace
} // namespace lray
