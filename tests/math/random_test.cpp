// Tests for src/math/random: counter-based streams are pure functions of
// their key; stratified ones are Owen-scrambled Sobol nets in each pair.
#include "math/random.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

namespace lray {
namespace {

TEST(Sampler, SameKeySameSequence) {
  Sampler a(3, 1234, 7), b(3, 1234, 7);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next(), b.next());
}

TEST(Sampler, DifferentKeysDiffer) {
  std::set<double> firsts;
  for (uint64_t px = 0; px < 1000; ++px) firsts.insert(Sampler(0, px, 0).next());
  EXPECT_EQ(firsts.size(), 1000u);
}

TEST(Sampler, UniformInUnitInterval) {
  Sampler s(1, 2, 3);
  double sum = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    double u = s.next();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
}

} // namespace
} // namespace lray

namespace lray {
namespace {

/// Whether points are a (0,m,2)-net: every elementary box of area 2^-m
/// (2^a by 2^(m-a) cells, for every a) holds exactly one.
bool isNet(const std::vector<std::pair<double, double>> &points, int m) {
  for (int a = 0; a <= m; ++a) {
    std::vector<int> count(size_t(1) << m, 0);
    for (const auto &[x, y] : points) {
      const int cx = static_cast<int>(x * (1 << a)), cy = static_cast<int>(y * (1 << (m - a)));
      if (++count[(size_t(cx) << (m - a)) | size_t(cy)] > 1) return false;
    }
  }
  return true;
}

TEST(Sampler, StratifiedPairsAreNetsOverAPixelsSamples) {
  // The path tracer's numbers: for the first 2^m samples of one pixel, each
  // pair of dimensions (next2D, whatever came before it) is a (0,m,2)-net;
  // the unstratified stream is not.
  constexpr int m = 6, n = 1 << m;
  const uint64_t pixelSeed = 0x1234567;
  for (int skip : {0, 1, 2, 3}) {
    SCOPED_TRACE(skip);
    std::vector<std::pair<double, double>> first, second, plain;
    for (uint32_t s = 0; s < n; ++s) {
      Sampler sampler(3, 77, s);
      Sampler unstratified = sampler;
      sampler.stratify(s, pixelSeed);
      for (int k = 0; k < skip; ++k) {
        sampler.next();
        unstratified.next();
      }
      double u, v;
      sampler.next2D(u, v);
      first.push_back({u, v});
      sampler.next2D(u, v);
      second.push_back({u, v});
      unstratified.next2D(u, v);
      plain.push_back({u, v});
    }
    EXPECT_TRUE(isNet(first, m));
    EXPECT_TRUE(isNet(second, m));
    EXPECT_FALSE(isNet(plain, m));
    EXPECT_NE(first, second); // each pair scrambled and shuffled on its own
  }
}

TEST(Sampler, StratifiedNumbersArePureFunctionsOfTheirKey) {
  Sampler a(1, 2, 5), b(1, 2, 5);
  a.stratify(5, 99);
  b.stratify(5, 99);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(a.next(), b.next());
}

} // namespace
} // namespace lray
