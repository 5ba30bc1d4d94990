// Tests for src/math/next_double.h: nextUp and nextDown are
// std::nextafter(x, +-infinity), bit for bit, on random doubles of every
// magnitude and sign and on the special values.
#include "math/next_double.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace lray {
namespace {

TEST(NextDouble, IsNextafterTowardsTheInfinities) {
  using L = std::numeric_limits<double>;
  std::vector<double> values = {0.0,           -0.0,          L::denorm_min(), -L::denorm_min(),
                                L::min(),      -L::min(),     L::max(),        -L::max(),
                                L::infinity(), -L::infinity(), L::quiet_NaN(), 1.0,
                                -1.0,          L::epsilon()};
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200000; ++i) values.push_back(std::bit_cast<double>(rng()));
  for (double x : values) {
    const double up = std::nextafter(x, L::infinity()), down = std::nextafter(x, -L::infinity());
    if (std::isnan(x)) {
      EXPECT_TRUE(std::isnan(nextUp(x)));
      EXPECT_TRUE(std::isnan(nextDown(x)));
      continue;
    }
    ASSERT_EQ(std::bit_cast<uint64_t>(nextUp(x)), std::bit_cast<uint64_t>(up)) << x;
    ASSERT_EQ(std::bit_cast<uint64_t>(nextDown(x)), std::bit_cast<uint64_t>(down)) << x;
  }
}

} // namespace
} // namespace lray
