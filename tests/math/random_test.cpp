// Tests for src/math/random: counter-based streams are pure functions of their key.
#include "math/random.h"

#include <gtest/gtest.h>

#include <set>

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
