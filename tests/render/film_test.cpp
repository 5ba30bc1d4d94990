// The film and its calloc-backed buffers (util/zeroed_vector.h): every value
// starts at 0 without being written, also in memory freed by a buffer before.
#include "render/film.h"
#include "util/zeroed_vector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

namespace lray {
namespace {

TEST(ZeroedVector, EveryElementIsZeroAlsoInReusedMemory) {
  // 64 KB (from the heap, where freed memory is handed out again) and
  // 12 MB (fresh pages from the kernel, by default).
  for (size_t count : {size_t{16} << 10, size_t{3} << 20})
    for (int round = 0; round < 3; ++round) {
      ZeroedVector<float> v(count);
      ASSERT_EQ(v.size(), count);
      EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](float x) { return x == 0.f; }))
          << count << " " << round;
      // Dirty it: the next round's vector likely gets this memory back.
      std::fill(v.begin(), v.end(), 7.f);
    }
  ZeroedVector<uint32_t> small(100);
  std::fill(small.begin(), small.end(), 9u);
  small.resize(1000); // grows into a new allocation: old values moved, new ones 0
  EXPECT_EQ(small[99], 9u);
  EXPECT_EQ(small[100], 0u);
  EXPECT_EQ(small[999], 0u);
  ZeroedVector<uint8_t> filled(10, 3); // a value is written as with std::vector
  EXPECT_EQ(filled[9], 3);
  const ZeroedVector<uint8_t> copy = filled;
  EXPECT_EQ(copy, filled);
}

TEST(Film, StartsBlackWithNoSamplesErrorOrVariance) {
  for (int round = 0; round < 2; ++round) {
    Film film(640, 360);
    for (int y = 0; y < film.height(); y += 7)
      for (int x = 0; x < film.width(); x += 5) {
        const Color c = film.get(x, y), v = film.variance(x, y);
        ASSERT_EQ(c.r + c.g + c.b, 0.0) << x << "," << y;
        ASSERT_EQ(v.r + v.g + v.b, 0.0) << x << "," << y;
        ASSERT_EQ(film.error(x, y), 0.f);
        ASSERT_EQ(film.sampleCount(x, y), 0u);
      }
    // Dirty it for the next round's film.
    for (int y = 0; y < film.height(); ++y)
      for (int x = 0; x < film.width(); ++x) {
        film.set(x, y, {1, 2, 3});
        film.setVariance(x, y, {1, 1, 1});
        film.setError(x, y, 1.f);
        film.setSampleCount(x, y, 5);
      }
  }
}

} // namespace
} // namespace lray
