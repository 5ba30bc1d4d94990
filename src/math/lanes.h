// Pipeline: math. Four doubles in one vector, an AVX register where the
// build targets AVX (LRAY_NATIVE) and SSE2 pairs on the baseline target:
// code that treats four rays, boxes or lanes at once with the scalar
// code's operations lane by lane, so that its decisions are the same bit
// for bit (the kd-tree's packets, accel/kdtree/packet_lanes.h; four rays'
// fields, math/ray_lanes.h).
#pragma once

#include <cstdint>
#include <cstring>
#include <emmintrin.h>
#ifdef __AVX__
#include <immintrin.h>
#endif

namespace lray::lanes {

constexpr int kWidth = 4;
// 32-byte vectors, whose passing by value differs between the baseline and
// AVX ABIs: the functions here take and give them by reference (-Wpsabi).
using Lanes = double __attribute__((vector_size(kWidth * sizeof(double))));
using Mask = int64_t __attribute__((vector_size(kWidth * sizeof(int64_t))));

/// x in every lane.
[[gnu::always_inline]] inline void splat(double x, Lanes &out) { out = Lanes{x, x, x, x}; }

/// Four doubles from memory (any alignment).
[[gnu::always_inline]] inline void load(const double *p, Lanes &out) {
  std::memcpy(&out, p, sizeof out);
}

/// std::fabs lane-wise, in place: the sign bits cleared.
[[gnu::always_inline]] inline void clearSigns(Lanes &v) {
  Mask bits;
  std::memcpy(&bits, &v, sizeof v);
  bits &= ~(Mask{} + INT64_MIN);
  std::memcpy(&v, &bits, sizeof v);
}

/// std::sqrt lane-wise, in place: IEEE square roots are correctly rounded,
/// so the SIMD instruction gives the scalar one's bits (without its errno
/// branch).
[[gnu::always_inline]] inline void sqrtInPlace(Lanes &v) {
#ifdef __AVX__
  __m256d x;
  std::memcpy(&x, &v, sizeof x);
  x = _mm256_sqrt_pd(x);
  std::memcpy(&v, &x, sizeof x);
#else
  __m128d lo, hi;
  std::memcpy(&lo, &v, sizeof lo);
  std::memcpy(&hi, reinterpret_cast<const char *>(&v) + sizeof lo, sizeof hi);
  lo = _mm_sqrt_pd(lo);
  hi = _mm_sqrt_pd(hi);
  std::memcpy(&v, &lo, sizeof lo);
  std::memcpy(reinterpret_cast<char *>(&v) + sizeof lo, &hi, sizeof hi);
#endif
}

/// Bit k set where lane k of a comparison's mask is true.
[[gnu::always_inline]] inline uint32_t bits(const Mask &m) {
#ifdef __AVX__
  __m256d v;
  std::memcpy(&v, &m, sizeof v);
  return static_cast<uint32_t>(_mm256_movemask_pd(v));
#else
  __m128d lo, hi;
  std::memcpy(&lo, &m, sizeof lo);
  std::memcpy(&hi, reinterpret_cast<const char *>(&m) + sizeof lo, sizeof hi);
  return static_cast<uint32_t>(_mm_movemask_pd(lo) | _mm_movemask_pd(hi) << 2);
#endif
}

/// error_bound.h's maxAbsComponent of (x, y, z), lane by lane:
/// std::max(|x|, std::max(|y|, |z|)), std::max(a, b) being a < b ? b : a.
[[gnu::always_inline]] inline void maxAbsComponent(const Lanes &x, const Lanes &y,
                                                   const Lanes &z, Lanes &out) {
  Lanes ax = x, ay = y, az = z;
  clearSigns(ax);
  clearSigns(ay);
  clearSigns(az);
  const Lanes yz = ay < az ? az : ay;
  out = ax < yz ? yz : ax;
}

} // namespace lray::lanes
