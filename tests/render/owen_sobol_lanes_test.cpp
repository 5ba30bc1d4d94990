// Tests for src/render/owen_sobol_lanes: the tile loop's eight-lane pixel
// positions are owenSobol2D's, bit for bit, on either path.
#include "render/owen_sobol_lanes.h"

#include "math/mix64.h"
#include "util/cpu_features.h"

#include <gtest/gtest.h>

#include <cstring>

namespace lray {
namespace {

/// Lanes of eight pixels' scrambles from seeds derived from `base`.
OwenLanes lanesFrom(uint64_t base, uint64_t (&seeds)[kOwenLanes]) {
  OwenLanes lanes{};
  for (size_t k = 0; k < kOwenLanes; ++k) {
    seeds[k] = mix64(base * 8 + k);
    lanes.set(k, owenScramble(seeds[k]));
  }
  return lanes;
}

void expectSameBits(double a, double b, uint32_t index, size_t lane) {
  uint64_t x, y;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  ASSERT_EQ(x, y) << "index " << index << ", lane " << lane;
}

void checkPath(bool avx2) {
  for (uint64_t base = 0; base < 64; ++base) {
    uint64_t seeds[kOwenLanes];
    const OwenLanes lanes = lanesFrom(base, seeds);
    // Small indices (a pixel's first samples) and large ones (every bit
    // of the index and the tables' upper bytes).
    for (uint32_t index : {0u, 1u, 2u, 3u, 7u, 15u, 16u, 255u, 256u, 65537u, 0x00ffffffu,
                           0x12345678u, 0x80000000u, 0xffffffffu, static_cast<uint32_t>(base)}) {
      for (size_t count = 1; count <= kOwenLanes; ++count) {
        double u[kOwenLanes], v[kOwenLanes];
        for (double &d : u) d = -1;
        for (double &d : v) d = -1;
        detail::owenSobol2DLanes(owen_detail::reverseBits(index), lanes.rows(), count, u, v, avx2);
        for (size_t k = 0; k < kOwenLanes; ++k) {
          if (k >= count) { // lanes past count are not written
            EXPECT_EQ(u[k], -1);
            EXPECT_EQ(v[k], -1);
            continue;
          }
          double x, y;
          owenSobol2D(index, seeds[k], x, y);
          expectSameBits(u[k], x, index, k);
          expectSameBits(v[k], y, index, k);
        }
      }
    }
  }
}

TEST(OwenSobol2DLanes, ScalarPathIsOwenSobol2D) { checkPath(false); }

TEST(OwenSobol2DLanes, Avx2PathIsOwenSobol2D) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkPath(true);
}

TEST(OwenSobol2DLanes, PositionsStayInThePixel) {
  uint64_t seeds[kOwenLanes];
  const OwenLanes lanes = lanesFrom(7, seeds);
  for (uint32_t index = 0; index < 1024; ++index) {
    double u[kOwenLanes], v[kOwenLanes];
    owenSobol2DLanes(owen_detail::reverseBits(index), lanes.rows(), kOwenLanes, u, v);
    for (size_t k = 0; k < kOwenLanes; ++k) {
      ASSERT_GE(u[k], 0.0);
      ASSERT_LT(u[k], 1.0);
      ASSERT_GE(v[k], 0.0);
      ASSERT_LT(v[k], 1.0);
    }
  }
}

} // namespace
} // namespace lray
