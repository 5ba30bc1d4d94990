// Tests for src/shading/pigments/perlin_noise: the properties of improved noise that
// the marble and wood pigments rely on, and the turbulence octave sum.
#include "shading/pigments/perlin_noise.h"

#include "math/random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lray {
namespace {

TEST(PerlinNoise, ZeroAtIntegerLatticePoints) {
  for (int x = -3; x <= 3; ++x) {
    for (int y = -3; y <= 3; ++y) {
      for (int z = -3; z <= 3; ++z) {
        EXPECT_EQ(perlinNoise(Vec3(x, y, z)), 0.0) << x << " " << y << " " << z;
      }
    }
  }
  EXPECT_EQ(perlinNoise(Vec3(1000, -4096, 77)), 0.0);
}

TEST(PerlinNoise, BoundedAndNotConstant) {
  Sampler s(1, 2, 3);
  double lo = 0, hi = 0;
  for (int i = 0; i < 200000; ++i) {
    Vec3 p{(s.next() - 0.5) * 40, (s.next() - 0.5) * 40, (s.next() - 0.5) * 40};
    double n = perlinNoise(p);
    ASSERT_TRUE(std::isfinite(n));
    lo = std::min(lo, n);
    hi = std::max(hi, n);
  }
  EXPECT_GE(lo, -1.0);
  EXPECT_LE(hi, 1.0);
  // Gradient noise spreads well beyond half its range in both directions.
  EXPECT_LT(lo, -0.5);
  EXPECT_GT(hi, 0.5);
}

TEST(PerlinNoise, Continuous) {
  Sampler s(7, 0, 0);
  for (int i = 0; i < 2000; ++i) {
    Vec3 p{(s.next() - 0.5) * 20, (s.next() - 0.5) * 20, (s.next() - 0.5) * 20};
    Vec3 q = p + Vec3(1e-7, -1e-7, 1e-7);
    // The gradient is bounded (a few units), so a 1e-7 step moves little.
    EXPECT_NEAR(perlinNoise(p), perlinNoise(q), 1e-5);
  }
  // Across a lattice cell boundary as well.
  EXPECT_NEAR(perlinNoise({1 - 1e-9, 0.3, 0.7}), perlinNoise({1 + 1e-9, 0.3, 0.7}), 1e-7);
  EXPECT_NEAR(perlinNoise({-1e-9, 0.3, 0.7}), perlinNoise({1e-9, 0.3, 0.7}), 1e-7);
}

TEST(PerlinNoise, RepeatsEvery256AndIsDeterministic) {
  Vec3 p{0.37, -1.61, 2.29};
  EXPECT_NEAR(perlinNoise(p), perlinNoise(p + Vec3(256, 0, 0)), 1e-12);
  EXPECT_NEAR(perlinNoise(p), perlinNoise(p + Vec3(0, -512, 256)), 1e-12);
  EXPECT_EQ(perlinNoise(p), perlinNoise(p));
  EXPECT_NE(perlinNoise(p), 0.0);
}

TEST(PerlinNoise, NonFiniteAndHugeInputsStayFinite) {
  double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(perlinNoise({inf, 0, 0}), 0.0);
  EXPECT_EQ(perlinNoise({std::nan(""), 0, 0}), 0.0);
  EXPECT_TRUE(std::isfinite(perlinNoise({1e30, -1e25, 3.5})));
}

TEST(PerlinNoise, TurbulenceSumsOctavesDownToSize) {
  Vec3 p{0.31, 1.77, -2.43};
  double expected = std::fabs(perlinNoise(p)) + std::fabs(perlinNoise(p * 2)) / 2 +
                    std::fabs(perlinNoise(p * 4)) / 4; // 1, 1/2, 1/4 >= 0.2 > 1/8
  EXPECT_DOUBLE_EQ(turbulence(p, 0.2), expected);
  EXPECT_DOUBLE_EQ(turbulence(p, 0.25), expected); // 2^-2 == size still counts
  EXPECT_DOUBLE_EQ(turbulence(p, 1.0), std::fabs(perlinNoise(p)));
  EXPECT_EQ(turbulence(p, 2.0), 0.0);
  // size <= 0 must terminate (bounded octave count) with a finite value.
  EXPECT_TRUE(std::isfinite(turbulence(p, 0.0)));
  EXPECT_TRUE(std::isfinite(turbulence(p, -1.0)));
}

} // namespace
} // namespace lray
