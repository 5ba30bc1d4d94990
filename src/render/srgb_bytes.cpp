// Pipeline: render (last stage). See srgb_bytes.h.
#include "render/srgb_bytes.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

namespace lray {

namespace {

constexpr uint32_t kOneBits = 0x3F800000; // 1.0f
/// Table entries per value: the bits of a float in [0, 1] shifted this far
/// right (16,257 entries; within one, the byte rises by at most about 0.9).
constexpr int kShift = 16;

/// The bits of `value` clamped to [0, 1], NaN and -0 as 0.
uint32_t unitBits(float value) {
  if (!(value > 0.f)) return 0; // NaN, negative, -0
  return std::min(std::bit_cast<uint32_t>(value), kOneBits);
}

struct Table {
  /// threshold[k]: the bits of the least value in [0, 1] whose byte is at
  /// least k (threshold[0] = 0); threshold[256] past every value.
  std::array<uint32_t, 257> threshold{};
  /// Per entry, the byte of its least value.
  std::array<uint8_t, (kOneBits >> kShift) + 1> first{};

  uint8_t byte(float value) const {
    const uint32_t bits = unitBits(value);
    int k = first[bits >> kShift];
    while (threshold[k + 1] <= bits) ++k;
    return static_cast<uint8_t>(k);
  }

  Table() {
    for (int k = 1; k <= 255; ++k) {
      // Least bits in [lo, hi] with a byte of at least k (hi's is 255).
      uint32_t lo = threshold[k - 1], hi = kOneBits;
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (srgbByteExact(std::bit_cast<float>(mid)) >= k) hi = mid;
        else lo = mid + 1;
      }
      threshold[k] = lo;
    }
    threshold[256] = kOneBits + 1;
    int k = 0;
    for (uint32_t e = 0; e < first.size(); ++e) {
      while (threshold[k + 1] <= e << kShift) ++k;
      first[e] = static_cast<uint8_t>(k);
    }
  }
};

const Table &table() {
  static const Table t;
  return t;
}

} // namespace

uint8_t srgbByteExact(float value) {
  float v = unitClamp(value);
  v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
  return round255(std::clamp(v, 0.f, 1.f));
}

uint8_t srgbByte(float value) { return table().byte(value); }

void srgbBytes(const float *in, uint8_t *out, size_t n) {
  const Table &t = table();
  for (size_t i = 0; i < n; ++i) out[i] = t.byte(in[i]);
}

} // namespace lray
