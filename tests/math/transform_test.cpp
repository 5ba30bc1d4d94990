// Tests for src/math/transform: conventions of SPEC 3 and inversion.
#include "math/transform.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

void expectNear(const Vec3 &a, const Vec3 &b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Transform, RotateFollowsSpecConvention) {
  expectNear(Transform::rotate({0, 1, 0}, 90).applyPoint({1, 0, 0}), {0, 0, -1});
  expectNear(Transform::rotate({0, 0, 1}, 90).applyPoint({1, 0, 0}), {0, 1, 0});
  expectNear(Transform::rotate({0, 0, 5}, 90).applyPoint({1, 0, 0}), {0, 1, 0}); // axis normalised
  expectNear(Transform::rotate({1, 0, 0}, 90).applyPoint({0, 1, 0}), {0, 0, 1});
}

TEST(Transform, RotateByQuarterTurnsIsExact) {
  Vec3 p = Transform::rotate({0, 1, 0}, 270).applyPoint({1, 0, 0});
  EXPECT_EQ(p, Vec3(0, 0, 1));
  EXPECT_EQ(Transform::rotate({0, 1, 0}, -90).applyPoint({1, 0, 0}), Vec3(0, 0, 1));
}

TEST(Transform, ComposeAppliesRightOperandFirst) {
  Transform t = Transform::translate({1, 0, 0}) * Transform::scale(2, 2, 2);
  expectNear(t.applyPoint({1, 1, 1}), {3, 2, 2});
  Transform u = Transform::scale(2, 2, 2) * Transform::translate({1, 0, 0});
  expectNear(u.applyPoint({1, 1, 1}), {4, 2, 2});
}

TEST(Transform, InverseUndoes) {
  Transform t = Transform::rotate({1, 2, 3}, 37) * Transform::translate({4, -5, 6}) *
                Transform::scale(0.5, 2, 3);
  Vec3 p{0.3, -7, 11};
  expectNear(t.inverse().applyPoint(t.applyPoint(p)), p, 1e-12);
  expectNear(t.applyPoint(t.inverse().applyPoint(p)), p, 1e-12);
}

TEST(Transform, NormalsUseInverseTranspose) {
  Transform t = Transform::scale(1, 4, 1);
  // Plane x + y = 0 has normal (1,1,0); after scaling y by 4 the plane is x + y/4 = 0.
  Vec3 n = normalize(t.applyNormal({1, 1, 0}));
  expectNear(n, normalize(Vec3(1, 0.25, 0)));
}

TEST(Transform, SingularMatricesAreFlagged) {
  EXPECT_TRUE(Transform::scale(0, 1, 1).singular());
  EXPECT_FALSE(Transform::scale(1e-6, 1, 1).singular());
  EXPECT_TRUE(Transform::rotate({0, 0, 0}, 30).singular());
  EXPECT_TRUE(Transform::lookAt({0, 0, 0}, {0, 1, 0}, {0, 1, 0}).singular());
  EXPECT_TRUE(Transform::lookAt({1, 1, 1}, {1, 1, 1}, {0, 1, 0}).singular());
  EXPECT_TRUE((Transform::translate({1, 0, 0}) * Transform::scale(1, 0, 1)).singular());
}

TEST(Transform, LookAtPointsZAtTarget) {
  Transform t = Transform::lookAt({0, 0, -5}, {0, 0, 0}, {0, 1, 0});
  expectNear(t.applyPoint({0, 0, 0}), {0, 0, -5});
  expectNear(t.applyVector({0, 0, 1}), {0, 0, 1});
  Transform u = Transform::lookAt({5, 0, 0}, {0, 0, 0}, {0, 1, 0});
  expectNear(u.applyVector({0, 0, 1}), {-1, 0, 0});
  expectNear(u.applyVector({0, 1, 0}), {0, 1, 0});
  // Left-handed: x is to the right of the view direction with y up.
  expectNear(u.applyVector({1, 0, 0}), {0, 0, 1});
}

} // namespace
} // namespace lray
