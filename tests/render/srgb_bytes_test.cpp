// Tests for src/render/srgb_bytes: the table's bytes are the formula's.
#include "render/srgb_bytes.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace lray {
namespace {

TEST(SrgbBytes, TheTableGivesTheFormulasByte) {
  // A stride through every float in [0, 1] (past the table's entries of
  // 2^16 floats many times over) and every float within 1024 of each
  // point where the formula's byte changes.
  size_t checked = 0;
  auto check = [&](float v) {
    ASSERT_EQ(srgbByte(v), srgbByteExact(v)) << v;
    ++checked;
  };
  for (uint32_t bits = 0; bits <= 0x3F800000u; bits += 127) check(std::bit_cast<float>(bits));
  uint32_t previous = 0;
  for (uint32_t bits = 0; bits <= 0x3F800000u; bits += 1u << 12) {
    const uint8_t here = srgbByteExact(std::bit_cast<float>(bits));
    if (bits > 0 && here != srgbByteExact(std::bit_cast<float>(previous)))
      for (uint32_t b = previous > 1024 ? previous - 1024 : 0; b <= bits + 1024; ++b)
        check(std::bit_cast<float>(std::min(b, 0x3F800000u)));
    previous = bits;
  }
  EXPECT_GT(checked, 8000000u);
}

TEST(SrgbBytes, OutOfRangeValuesAreClamped) {
  const float inf = std::numeric_limits<float>::infinity();
  for (float v : {-0.f, -1.f, -inf, std::nanf(""), -std::nanf(""), 0x1p-149f})
    EXPECT_EQ(srgbByte(v), 0) << v;
  for (float v : {1.f, 1.5f, inf}) EXPECT_EQ(srgbByte(v), 255) << v;
  EXPECT_EQ(srgbByte(0.5f), 188); // sRGB(0.5) = 0.7354
  EXPECT_EQ(srgbByte(0.002f), 7); // linear segment: 12.92 * 0.002 * 255 = 6.6
  EXPECT_EQ(srgbByte(std::nextafter(1.f, 0.f)), 255);
}

} // namespace
} // namespace lray
