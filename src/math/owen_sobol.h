// Pipeline: shared math. Pixel sample positions for progressive (adaptive)
// sampling: the first two dimensions of the Sobol sequence, Owen-scrambled
// with a per-pixel seed (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4)). Every prefix of 2^m samples is a (0,m,2)-net, so
// a pixel's samples stay stratified wherever the adaptive sampler stops it,
// and the scramble decorrelates neighbouring pixels. Also the path tracer's
// pairs of dimensions (math/random.h, Sampler::stratify).
#pragma once

#include "math/mix64.h"

#include <cstdint>

namespace lray {

namespace owen_detail {

inline uint32_t reverseBits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  return __builtin_bswap32(x); // each byte is reversed: reverse their order
}

/// A hash in which each bit depends only on the bits below it: applied to
/// bit-reversed values it flips each digit depending only on the digits
/// above it, which is Owen's nested uniform scramble (Laine and Karras 2011;
/// constants from Burley 2020).
inline uint32_t laineKarras(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

inline uint32_t nestedScramble(uint32_t x, uint32_t seed) {
  return reverseBits(laineKarras(reverseBits(x), seed));
}

/// Sobol dimension 2 (the first is the van der Corput sequence): its
/// direction numbers are v_0 = 2^31, v_i = v_{i-1} ^ (v_{i-1} >> 1), and
/// point i is the xor of v_j over the set bits j of i. The indices here are
/// scrambled, so about half of their 32 bits are set at random: a loop
/// over the bits mispredicts a branch per bit (it was a third of a simple
/// scene's render, bench/throughput). Instead, each byte of the index looks
/// up the xor of its eight direction numbers. The table holds them bit-
/// reversed (reversal commutes with xor), as the nested scramble wants them.
struct SobolSecondTable {
  uint32_t byByte[4][256];
};

constexpr SobolSecondTable makeSobolSecondTable() {
  SobolSecondTable table{};
  uint32_t v[32] = {}; // reversed: v_0 = 1, v_i = v_{i-1} ^ (v_{i-1} << 1)
  v[0] = 1;
  for (int j = 1; j < 32; ++j) v[j] = v[j - 1] ^ (v[j - 1] << 1);
  for (int k = 0; k < 4; ++k)
    for (uint32_t b = 0; b < 256; ++b) {
      uint32_t x = 0;
      for (int j = 0; j < 8; ++j)
        if ((b >> j) & 1) x ^= v[8 * k + j];
      table.byByte[k][b] = x;
    }
  return table;
}

inline constexpr SobolSecondTable kSobolSecond = makeSobolSecondTable();

/// reverseBits(sobolSecond(index)).
inline uint32_t sobolSecondReversed(uint32_t index) {
  const auto &t = kSobolSecond.byByte;
  return t[0][index & 255] ^ t[1][(index >> 8) & 255] ^ t[2][(index >> 16) & 255] ^
         t[3][index >> 24];
}

inline uint32_t sobolSecond(uint32_t index) { return reverseBits(sobolSecondReversed(index)); }

} // namespace owen_detail

/// What owenSobol2D draws from a pixel's scramble seed: the same for all of
/// the pixel's samples, so a loop over many of them makes it once
/// (owenScramble).
struct OwenScramble {
  uint32_t shuffle = 0, sx = 0, sy = 0;
};

inline OwenScramble owenScramble(uint64_t seed) {
  return {static_cast<uint32_t>(seed >> 32), static_cast<uint32_t>(mix64(seed)),
          static_cast<uint32_t>(mix64(seed ^ 0x5851f42d4c957f2dULL))};
}

/// owenSobol2D of the index whose bits reversed are `reversedIndex`, with
/// the pixel's scramble made ahead: the same values. The tile loop takes
/// sample s of a tile's pixels in turn, so it reverses s once for all of
/// them and makes each pixel's scramble once for all of its samples
/// (render/owen_sobol_lanes.h).
[[gnu::always_inline]] inline void owenSobol2DReversed(uint32_t reversedIndex,
                                                        const OwenScramble &scramble, double &x,
                                                        double &y) {
  using namespace owen_detail;
  // nestedScramble(index, shuffle), its first reversal given.
  const uint32_t i = reverseBits(laineKarras(reversedIndex, scramble.shuffle));
  // nestedScramble(reverseBits(i), sx), with its two reversals cancelled.
  x = reverseBits(laineKarras(i, scramble.sx)) * 0x1.0p-32;
  y = reverseBits(laineKarras(sobolSecondReversed(i), scramble.sy)) * 0x1.0p-32; // nestedScramble
}

/// Sample `index` of the pixel whose scramble seed is `seed`: a position in
/// [0,1)^2 inside the pixel. The index is shuffled first (an Owen scramble
/// of the index, which maps every aligned block of 2^m indices onto an
/// aligned block of 2^m Sobol points, so prefixes stay nets): without it,
/// Sobol points 2k and 2k+1 always fall in opposite halves of the pixel,
/// and whatever a sample's parity chooses (a light share under spread
/// sampling, say) would see only one side of an edge however many samples
/// a pixel took. Always inlined: the path tracer calls it for each pair of
/// stratified dimensions (Sampler::next2D).
[[gnu::always_inline]] inline void owenSobol2D(uint32_t index, uint64_t seed, double &x,
                                                double &y) {
  owenSobol2DReversed(owen_detail::reverseBits(index), owenScramble(seed), x, y);
}

/// Sample `index` of a one-dimensional stratified sequence in [0, 1) whose
/// scramble seed is `seed` (the first coordinate of owenSobol2D): every
/// prefix of 2^m samples has one in each interval of length 2^-m.
inline double owenSobol1D(uint32_t index, uint64_t seed) {
  using namespace owen_detail;
  const uint32_t i = nestedScramble(index, static_cast<uint32_t>(seed >> 32));
  return reverseBits(laineKarras(i, static_cast<uint32_t>(mix64(seed)))) * 0x1.0p-32;
}

} // namespace lray
