// Pipeline: render. owenSobol2DLanes (owen_sobol_lanes.h): the scalar
// path, and the same arithmetic in eight 32-bit AVX2 lanes.
#include "render/owen_sobol_lanes.h"

#include "util/cpu_features.h"

#include <immintrin.h>

namespace lray {

namespace {

#define LRAY_AVX2 __attribute__((target("avx2")))

/// laineKarras in each lane.
LRAY_AVX2 inline __m256i laineKarrasLanes(__m256i x, __m256i seed) {
  constexpr uint32_t kMultipliers[] = {0x6c50b47cu, 0xb82f1e52u, 0xc7afe638u, 0x8d22f6e6u};
  x = _mm256_add_epi32(x, seed);
  for (uint32_t c : kMultipliers)
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(static_cast<int>(c))));
  return x;
}

/// reverseBits in each lane: each byte's bits reversed by two nibble
/// lookups, then the bytes' order within the lane.
LRAY_AVX2 inline __m256i reverseBitsLanes(__m256i x) {
  // Nibble n reversed (as a 4-bit value), in both 128-bit halves.
  const __m256i reversed = _mm256_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5,
                                            0xd, 0x3, 0xb, 0x7, 0xf, 0x0, 0x8, 0x4, 0xc, 0x2, 0xa,
                                            0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf);
  const __m256i nibble = _mm256_set1_epi8(0x0f);
  const __m256i lo = _mm256_and_si256(x, nibble);
  const __m256i hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), nibble);
  // The low nibble reversed goes high: each looked-up byte is at most 0x0f,
  // so the 16-bit shift moves no bit into the next byte.
  const __m256i bytes = _mm256_or_si256(_mm256_slli_epi16(_mm256_shuffle_epi8(reversed, lo), 4),
                                        _mm256_shuffle_epi8(reversed, hi));
  const __m256i order = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3,
                                         2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
  return _mm256_shuffle_epi8(bytes, order);
}

/// sobolSecondReversed in each lane: the four byte tables gathered.
LRAY_AVX2 inline __m256i sobolSecondReversedLanes(__m256i index) {
  const auto &t = owen_detail::kSobolSecond.byByte;
  const __m256i byte = _mm256_set1_epi32(255);
  __m256i r = _mm256_setzero_si256();
  for (int k = 0; k < 4; ++k) {
    const __m256i b = _mm256_and_si256(_mm256_srli_epi32(index, 8 * k), byte);
    r = _mm256_xor_si256(r, _mm256_i32gather_epi32(reinterpret_cast<const int *>(t[k]), b, 4));
  }
  return r;
}

/// Each lane's unsigned value times 2^-32, as owenSobol2DReversed's
/// conversion: the signed conversion of x - 2^31 plus 2^31 is exact, and so
/// is the product; `count` lanes stored.
LRAY_AVX2 inline void storeFractions(__m256i x, size_t count, double *out) {
  const __m256i flipped = _mm256_xor_si256(x, _mm256_set1_epi32(INT32_MIN));
  const __m256d offset = _mm256_set1_pd(2147483648.0), scale = _mm256_set1_pd(0x1.0p-32);
  alignas(32) double all[kOwenLanes];
  for (int half = 0; half < 2; ++half) {
    const __m128i part = half ? _mm256_extracti128_si256(flipped, 1)
                              : _mm256_castsi256_si128(flipped);
    const __m256d d = _mm256_mul_pd(_mm256_add_pd(_mm256_cvtepi32_pd(part), offset), scale);
    _mm256_store_pd(all + 4 * half, d);
  }
  for (size_t k = 0; k < count; ++k) out[k] = all[k];
}

LRAY_AVX2 inline __m256i load(const uint32_t *row) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i *>(row));
}

LRAY_AVX2 void sobolLanesAvx2(uint32_t reversedIndex, const OwenRows &rows, size_t count,
                              double *u, double *v) {
  const __m256i i = reverseBitsLanes(
      laineKarrasLanes(_mm256_set1_epi32(static_cast<int>(reversedIndex)), load(rows.shuffle)));
  storeFractions(reverseBitsLanes(laineKarrasLanes(i, load(rows.sx))), count, u);
  storeFractions(reverseBitsLanes(laineKarrasLanes(sobolSecondReversedLanes(i), load(rows.sy))),
                 count, v);
}

} // namespace

namespace detail {

void owenSobol2DLanes(uint32_t reversedIndex, const OwenRows &rows, size_t count, double *u,
                      double *v, bool avx2) {
  if (avx2) return sobolLanesAvx2(reversedIndex, rows, count, u, v);
  for (size_t k = 0; k < count; ++k)
    owenSobol2DReversed(reversedIndex, {rows.shuffle[k], rows.sx[k], rows.sy[k]}, u[k], v[k]);
}

} // namespace detail

void owenSobol2DLanes(uint32_t reversedIndex, const OwenRows &rows, size_t count, double *u,
                      double *v) {
  detail::owenSobol2DLanes(reversedIndex, rows, count, u, v, cpuHasAvx2());
}

} // namespace lray
