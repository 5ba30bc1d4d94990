// Pipeline: render (last stage). The 8-bit values an LDR file holds: a
// value clamped and rounded, and the 8-bit sRGB value of a linear-light
// value (`lray --linear`, README.md): the transfer curve's power, once per
// channel of every pixel, was most of a linear-workflow PNG's encoding.
// srgbByte gives the very byte the formula (srgbByteExact) gives, from a
// table: the formula is non-decreasing in its argument, so its bytes are
// told apart by 255 thresholds, found once by bisection on the formula.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace lray {

/// `value` clamped to [0, 1], NaN as 0.
inline float unitClamp(float value) {
  return std::isnan(value) ? 0.f : std::clamp(value, 0.f, 1.f);
}

/// v in [0, 1] times 255, rounded half away from zero as std::lround does,
/// without its call (a tenth of a light animation's time went to it): for
/// x in [0, 255], x - trunc(x) is exact (Sterbenz), so the test against 0.5
/// is too. Inline and branch-free, so that a frame's loop is vectorized
/// (image_writer.cpp's linear values; srgbByteExact's encoded ones).
inline uint8_t round255(float v) {
  const float x = v * 255.f;
  const int whole = static_cast<int>(x);
  return static_cast<uint8_t>(whole + (x - static_cast<float>(whole) >= 0.5f ? 1 : 0));
}

/// The sRGB transfer curve of `value` clamped to [0, 1] (NaN as 0), times
/// 255, rounded half away from zero: the formula, a power per call.
uint8_t srgbByteExact(float value);

/// srgbByteExact(value), bit for bit, without the power: a table look-up
/// by the value's leading bits and at most a few comparisons against the
/// thresholds (the table is built on first use, about 8,000 powers).
uint8_t srgbByte(float value);

/// out[i] = srgbByte(in[i]) for i < n (the table found once).
void srgbBytes(const float *in, uint8_t *out, size_t n);

} // namespace lray
