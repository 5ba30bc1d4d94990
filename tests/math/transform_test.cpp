// Tests for src/math/transform: conventions of lua/README.md, "Values" and inversion.
#include "math/transform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

TEST(Transform, CachesIdentityAndErrorNorms) {
  EXPECT_TRUE(Transform().isIdentity());
  Transform shift = Transform::translate({1, 2, 3});
  EXPECT_FALSE(shift.isIdentity());
  EXPECT_TRUE((shift * shift.inverse()).isIdentity());
  Transform xf = Transform::translate({1, -5, 2}) * Transform::rotate({1, 2, 3}, 37) *
                 Transform::scale(2, -3, 0.5);
  for (const Transform &t : {xf, xf.inverse(), shift, Transform::scale(1, 4, 2)}) {
    // Recompute from the matrices: largest absolute row sums and translations.
    double rows[4] = {0, 0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      double r = 0, ri = 0;
      for (int j = 0; j < 3; ++j) {
        r += std::fabs(t.matrix().m[i][j]);
        ri += std::fabs(t.inverseMatrix().m[i][j]);
      }
      rows[0] = std::max(rows[0], r);
      rows[1] = std::max(rows[1], ri);
      rows[2] = std::max(rows[2], std::fabs(t.matrix().m[i][3]));
      rows[3] = std::max(rows[3], std::fabs(t.inverseMatrix().m[i][3]));
    }
    EXPECT_EQ(t.linearNorm(), rows[0]);
    EXPECT_EQ(t.inverseLinearNorm(), rows[1]);
    EXPECT_EQ(t.translationNorm(), rows[2]);
    EXPECT_EQ(t.inverseTranslationNorm(), rows[3]);
  }
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
