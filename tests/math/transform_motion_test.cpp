// Tests for src/math/transform_motion: decomposition round trips, the
// interpolation of turns (no shrinking, an even rate), exact steps, and
// swept bounds that hold the moving box at every time.
#include "math/transform_motion.h"

#include "math/random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

namespace lray {
namespace {

const Vec3 kY{0, 1, 0}, kZ{0, 0, 1};

void expectNear(const Mat4 &a, const Mat4 &b, double tol) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << i << "," << j;
}

TEST(TransformMotion, DecomposeThenComposeGivesTheMatrixBack) {
  const Transform shearedScaled = Transform::translate({3, -2, 7}) *
                                  Transform::rotate({1, 2, 3}, 50) * Transform::scale(2, 0.5, 3) *
                                  Transform::rotate({0, 1, 1}, 20);
  expectNear(compose(decompose(shearedScaled.matrix())), shearedScaled.matrix(), 1e-12);
  // A mirror: the rotation stays proper, the stretch takes the sign.
  const Transform mirrored = Transform::rotate(kY, 30) * Transform::scale(-1, 2, 1);
  const TransformParts parts = decompose(mirrored.matrix());
  const Quaternion &q = parts.rotation;
  EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1, 1e-14);
  expectNear(compose(parts), mirrored.matrix(), 1e-12);
}

TEST(TransformMotion, ASpinningWheelTurnsEvenlyAndKeepsItsSize) {
  // A third of a turn between the steps, about an axis through (1, 2, 0).
  const Transform place = Transform::translate({1, 2, 0}) * Transform::scale(2, 2, 2);
  const TransformMotion wheel({place, place * Transform::rotate(kZ, 120)});
  for (double t : {0.25, 0.5, 0.75}) {
    const Transform at = wheel.at(t);
    expectNear(at.matrix(), (place * Transform::rotate(kZ, 120 * t)).matrix(), 1e-12);
    EXPECT_NEAR(at.matrix().det3(), 8, 1e-12); // a linear blend of matrices gives 2
  }
  // Between steps, of a turning wheel, of one that also grows and of one
  // that only slides (its inverse made another way): the inverse is the
  // matrix's.
  const TransformMotion growing({place, Transform::translate({0, 1, 0}) *
                                            Transform::rotate(kZ, 60) * Transform::scale(3, 1, 2)});
  const TransformMotion sliding({place, Transform::translate({3, -1, 2}) * place});
  EXPECT_TRUE(sliding.slides());
  EXPECT_FALSE(wheel.slides());
  EXPECT_FALSE(growing.slides());
  for (const TransformMotion *m : {&wheel, &growing, &sliding})
    for (double t : {0.1, 0.5, 0.9}) {
      const Transform at = m->at(t);
      expectNear(at.matrix() * at.inverseMatrix(), Mat4::identity(), 1e-13);
      EXPECT_EQ(m->inverseMatrixAt(t), at.inverseMatrix());
      EXPECT_EQ(m->matrixAt(t), at.matrix());
    }
  // The steps themselves, bit for bit.
  EXPECT_EQ(wheel.at(0).matrix(), place.matrix());
  EXPECT_EQ(wheel.at(1).matrix(), (place * Transform::rotate(kZ, 120)).matrix());
  EXPECT_EQ(wheel.matrixAt(0.5), wheel.at(0.5).matrix());
}

TEST(TransformMotion, StepsSpreadEvenlyOverTheShutter) {
  std::vector<Transform> steps;
  for (int i = 0; i < 5; ++i)
    steps.push_back(Transform::translate({i * 1.0, i * i * 1.0, 0}));
  const TransformMotion m(steps);
  EXPECT_EQ(m.at(0.5).matrix(), steps[2].matrix());
  // Between steps 1 and 2 (times 0.25, 0.5): linear in that segment.
  expectNear(m.at(0.375).matrix(), Transform::translate({1.5, 2.5, 0}).matrix(), 1e-14);
  // Outside [0, 1]: clamped.
  EXPECT_EQ(m.at(2).matrix(), steps[4].matrix());
}

TEST(TransformMotion, AMotionBuiltWhereAnotherWasAnswersForItself) {
  // A later frame's motion may live where an earlier one did: its inverse
  // at the same time must be its own, whatever inverseMatrixAt remembers.
  std::optional<TransformMotion> m;
  m.emplace(std::vector<Transform>{Transform(), Transform::translate({1, 0, 0})});
  EXPECT_EQ(m->inverseMatrixAt(0.5).m[0][3], -0.5);
  m.emplace(std::vector<Transform>{Transform(), Transform::translate({3, 0, 0})});
  EXPECT_EQ(m->inverseMatrixAt(0.5).m[0][3], -1.5);
}

/// A box and a motion that slides, turns by 170 degrees while stretching,
/// and turns back about another axis: for the bounds tests.
const Bounds3 kBox({-1, -0.5, -2}, {1, 0.5, 2});
TransformMotion tumble() {
  return TransformMotion({Transform::translate({0, 0, 0}),
                          Transform::translate({3, 1, 0}) * Transform::rotate({1, 1, 0}, 170) *
                              Transform::scale(1, 2, 1),
                          Transform::translate({5, -1, 2}) * Transform::rotate({0, 1, 1}, 30)});
}

TEST(TransformMotion, SweptBoundsHoldTheBoxAtEveryTime) {
  const Bounds3 box = kBox;
  const TransformMotion m = tumble();
  const Bounds3 all = m.sweptBounds(box, 0, 1);
  const Bounds3 firstHalf = m.sweptBounds(box, 0, 0.5);
  Sampler random(1, 2, 3);
  double slack = 1e300;
  for (int i = 0; i < 20000; ++i) {
    const double t = random.next();
    const Vec3 p{random.next() * 2 - 1, random.next() - 0.5, random.next() * 4 - 2};
    // Corners too: they are where the box reaches furthest.
    const Vec3 c{p.x < 0 ? -1.0 : 1.0, p.y < 0 ? -0.5 : 0.5, p.z < 0 ? -2.0 : 2.0};
    for (const Vec3 &q : {p, c}) {
      const Vec3 w = m.at(t).applyPoint(q);
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(w[a], all.lo[a]);
        ASSERT_LE(w[a], all.hi[a]);
        slack = std::min({slack, w[a] - all.lo[a], all.hi[a] - w[a]});
        if (t <= 0.5) {
          ASSERT_GE(w[a], firstHalf.lo[a]);
          ASSERT_LE(w[a], firstHalf.hi[a]);
        }
      }
    }
  }
  // Not grossly loose: some corner comes within a tenth of a unit of it.
  EXPECT_LT(slack, 0.1);
  EXPECT_LT(firstHalf.hi.x, all.hi.x);
}

// What Embree does with a moving primitive's step bounds: blends two
// neighbouring steps' boxes linearly by the ray's time.
TEST(TransformMotion, BlendedStepBoundsHoldTheBoxAtEveryTime) {
  const Bounds3 box = kBox;
  const TransformMotion m = tumble();
  auto corners = [&](const Transform &xf) {
    Bounds3 b;
    for (int c = 0; c < 8; ++c)
      b.extend(xf.applyPoint({c & 1 ? 1.0 : -1.0, c & 2 ? 0.5 : -0.5, c & 4 ? 2.0 : -2.0}));
    return b;
  };
  std::vector<Bounds3> steps;
  for (size_t i = 0; i < m.stepCount(); ++i) steps.push_back(m.stepBounds(box, i, corners));
  Sampler random(4, 5, 6);
  double slack = 1e300;
  for (int i = 0; i < 20000; ++i) {
    const double t = random.next();
    const size_t segment = t < 0.5 ? 0 : 1;
    const double u = t * 2 - double(segment);
    const Bounds3 &a = steps[segment], &b = steps[segment + 1];
    const Vec3 c{random.next() < 0.5 ? -1.0 : 1.0, random.next() < 0.5 ? -0.5 : 0.5,
                 random.next() < 0.5 ? -2.0 : 2.0};
    const Vec3 w = m.at(t).applyPoint(c);
    for (int k = 0; k < 3; ++k) {
      const double lo = a.lo[k] + (b.lo[k] - a.lo[k]) * u, hi = a.hi[k] + (b.hi[k] - a.hi[k]) * u;
      ASSERT_GE(w[k], lo) << t;
      ASSERT_LE(w[k], hi) << t;
      slack = std::min({slack, w[k] - lo, hi - w[k]});
    }
  }
  EXPECT_LT(slack, 0.1);
  // Tighter than the bounds over the whole shutter.
  const Bounds3 all = m.sweptBounds(box, 0, 1);
  EXPECT_LT(steps[0].hi.x, all.hi.x - 1);
}

} // namespace
} // namespace lray
