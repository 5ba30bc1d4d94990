// The noise-aware test (compare/noise_test.h) on images whose pixels are
// means of simulated Gaussian samples: at the stated false-alarm rate over
// many independent pairs, and failing on a 1 % change, a small object and
// a NaN.
#include "compare/comparison.h"
#include "compare/noise_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <random>

using namespace lray::compare;

namespace {

/// A w x h render of a smooth picture (times `gain`, with an optional
/// patch of `patch` added), each pixel the mean of n samples of noise
/// sigma relative to the value, with its sample variance over n.
CompareImage simulate(uint32_t seed, int w = 64, int h = 48, double gain = 1, int n = 16,
                      double sigma = 0.3, double patch = 0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  CompareImage im;
  im.width = w;
  im.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        double truth = gain * (0.3 + 0.2 * std::sin(0.2 * x + c) * std::cos(0.15 * y));
        if (patch != 0 && x >= 20 && x < 23 && y >= 10 && y < 13) truth += patch;
        double sum = 0, squares = 0;
        for (int k = 0; k < n; ++k) {
          const double s = truth * (1 + sigma * normal(rng));
          sum += s;
          squares += s * s;
        }
        const double mean = sum / n;
        im.rgb.push_back(static_cast<float>(mean));
        im.variance.push_back(static_cast<float>((squares - sum * mean) / (n - 1) / n));
      }
      im.samples.push_back(static_cast<float>(n));
    }
  return im;
}

Criteria noise(double alpha) { return {.metric = Metric::Noise, .threshold = alpha}; }

} // namespace

TEST(NoiseTest, StudentsTailsAreRight) {
  EXPECT_NEAR(twoSidedP(1.959963984540054, 1e9), 0.05, 1e-9);
  EXPECT_NEAR(twoSidedP(2.228138851986274, 10), 0.05, 1e-9); // t table, 10 dof
  EXPECT_NEAR(twoSidedP(12.70620473617471, 1), 0.05, 1e-9);
  EXPECT_EQ(twoSidedP(0, 3), 1.0);
}

TEST(NoiseTest, TwoRendersOfOnePictureFailAtMostAtTheStatedRate) {
  // 200 independent pairs at alpha 0.05: at most 10 expected; 19 is beyond
  // 3 binomial standard deviations. A test that ignored the noise (or took
  // the standard deviation for the variance) fails most pairs.
  int failures = 0;
  for (uint32_t i = 0; i < 200; ++i) {
    const Outcome o = compareImages(simulate(2 * i + 1, 64, 48, 1, 8),
                                    simulate(2 * i + 2, 64, 48, 1, 8), noise(0.05));
    failures += !o.pass;
  }
  std::printf("%d of 200 pairs fail at alpha 0.05\n", failures);
  EXPECT_LE(failures, 19);
  // Holm is conservative under dependence but not blind: about alpha of
  // the pairs still fail (the pixel-level tests are independent).
  EXPECT_GE(failures, 3);
}

TEST(NoiseTest, AOnePercentChangeFails) {
  const Outcome o = compareImages(simulate(1, 64, 48, 1.01), simulate(2), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
  EXPECT_GT(o.noiseRejected, 0u);
}

TEST(NoiseTest, ASmallObjectMissingFails) {
  const Outcome o = compareImages(simulate(1), simulate(2, 64, 48, 1, 16, 0.3, 0.3), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
  // The heat map marks it.
  EXPECT_TRUE(o.flagged[11 * 64 + 21]);
}

TEST(NoiseTest, ANanPixelFails) {
  CompareImage a = simulate(1);
  a.rgb[(5 * 64 + 7) * 3 + 1] = std::nanf("");
  const Outcome o = compareImages(a, simulate(2), noise(0.01));
  EXPECT_FALSE(o.pass);
  EXPECT_EQ(o.nonFinite, 1u);
  EXPECT_TRUE(o.flagged[5 * 64 + 7]);
}

TEST(NoiseTest, NoiseFreePixelsMayDifferOnlyByRounding) {
  CompareImage a = simulate(1, 8, 8, 1, 16, 0), b = a;
  b.rgb[0] = std::nextafter(b.rgb[0], 1.f);
  EXPECT_TRUE(compareImages(a, b, noise(0.01)).pass);
  b.rgb[0] += 1e-3f;
  EXPECT_FALSE(compareImages(a, b, noise(0.01)).pass);
}

TEST(NoiseTest, ImagesWithoutVarianceAreAnError) {
  CompareImage a = simulate(1), b = simulate(2);
  b.variance.clear();
  EXPECT_THROW(compareImages(a, b, noise(0.01)), CompareError);
}

namespace {

/// `simulate`'s image as an 8-bit file holds it: clamped, rounded, no
/// variance.
CompareImage eightBit(CompareImage im) {
  for (float &v : im.rgb) v = std::round(std::clamp(v, 0.f, 1.f) * 255) / 255;
  im.variance.clear();
  im.samples.clear();
  im.quantum = 1.0 / 255;
  return im;
}

} // namespace

TEST(NoiseTestFromTwoRenders, PassesAtTheStatedRateAndFailsAChange) {
  // 8-bit images: the variance comes from two new renders at other seeds.
  int failures = 0;
  for (uint32_t i = 0; i < 200; ++i) {
    const CompareImage a = eightBit(simulate(3 * i + 1, 64, 48, 1, 8)),
                       b = eightBit(simulate(3 * i + 2, 64, 48, 1, 8)),
                       approved = eightBit(simulate(3 * i + 3, 64, 48, 1, 8));
    failures += !compareImages(a, approved, noise(0.05), &b).pass;
  }
  std::printf("%d of 200 8-bit triples fail at alpha 0.05\n", failures);
  EXPECT_LE(failures, 19);
  const CompareImage approved = eightBit(simulate(3)), a = eightBit(simulate(1)),
                     b = eightBit(simulate(2));
  EXPECT_TRUE(compareImages(a, approved, noise(0.01), &b).pass);
  const CompareImage brighter = eightBit(simulate(1, 64, 48, 1.03)),
                     brighter2 = eightBit(simulate(2, 64, 48, 1.03));
  EXPECT_FALSE(compareImages(brighter, approved, noise(0.01), &brighter2).pass);
  const CompareImage patched = eightBit(simulate(1, 64, 48, 1, 16, 0.3, 0.3)),
                     patched2 = eightBit(simulate(2, 64, 48, 1, 16, 0.3, 0.3));
  EXPECT_FALSE(compareImages(patched, approved, noise(0.01), &patched2).pass);
  // Without a second render, 8-bit files cannot be tested for noise.
  EXPECT_THROW(compareImages(a, approved, noise(0.01)), CompareError);
}
