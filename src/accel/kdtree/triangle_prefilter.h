// Pipeline: acceleration (kd-tree backend). A conservative float prefilter
// for the watertight triangle test (watertight_triangle.h): four triangles
// at once in SSE lanes compute the same sheared edge functions in float,
// with a rigorous bound on their distance from the double ones. A triangle
// is rejected only when two of its edge functions certainly have opposite
// signs, so the double test would reject it too; the others go on to that
// test, which alone decides hits, t and barycentrics. Results are the same
// as testing every triangle in double.
#pragma once

#include "accel/kdtree/watertight_triangle.h"
#include "math/bounds.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lray {

/// Four triangles' float corners, coordinate-major so that each coordinate
/// of a corner fills one SIMD register (lane = triangle).
struct alignas(16) TrianglePacket {
  float v[3][3][4]; ///< [corner][axis][lane]

  Vec3f corner(int lane, int c) const { return {v[c][0][lane], v[c][1][lane], v[c][2][lane]}; }
  void set(int lane, const Vec3f &p0, const Vec3f &p1, const Vec3f &p2) {
    const Vec3f *p[3] = {&p0, &p1, &p2};
    for (int c = 0; c < 3; ++c) {
      v[c][0][lane] = p[c]->x;
      v[c][1][lane] = p[c]->y;
      v[c][2][lane] = p[c]->z;
    }
  }
};

/// The ray of a WatertightRay in float for the prefilter, with the error
/// bounds of its float edge functions.
///
/// Error bound. With u = 2^-24, O >= |o| (every component) and P >= |p - o|
/// for every corner p, each float sheared coordinate x = (p_kx - o_kx) -
/// sx (p_kz - o_kz) (origin and shear rounded to float, three roundings)
/// lies within 2uO + 6uP + O(u^2) of its exact value (|sx|, |sy| <= 1: kz
/// is the dominant axis); `delta` is 3uO + 8uP. An edge function
/// e = cx by - cy bx from such coordinates, with S >= |x| + |y| for both
/// corners, lies within delta (2S + 2 delta) + 3u S^2 (1 + u) of its exact
/// value; the double test's error, by the same rule with 2^-53, is 2^-29 of
/// that, inside the margin of the constants below. Tiny magnitudes (float
/// underflow) get an absolute term. Beyond the bound, the float and double
/// values have the same strict sign.
struct PrefilterRay {
  float ox = 0, oy = 0, oz = 0, sx = 0, sy = 0; ///< origin (kx, ky, kz) and shear
  float delta = 0, delta2 = 0;                  ///< delta and 2 delta
  bool active = false; ///< false: magnitudes out of float range, every triangle passes
  /// The bound's other constants: gamma (3u S^2 (1 + u) with margin) and
  /// the absolute term.
  static constexpr float kGamma = static_cast<float>(3.03 * 0x1.0p-24), kTiny = 1e-30f;

  /// Inactive: every triangle passes.
  PrefilterRay() = default;
  /// `box` bounds every corner the prefilter will see (the mesh's bounds).
  PrefilterRay(const WatertightRay &ray, const Bounds3 &box) {
    double o = 0, p = 0;
    for (int a = 0; a < 3; ++a) {
      o = std::max(o, std::fabs(ray.o[a]));
      p = std::max({p, std::fabs(box.lo[a] - ray.o[a]), std::fabs(box.hi[a] - ray.o[a])});
    }
    constexpr double kLimit = 1e30;
    active = o < kLimit && p < kLimit;
    if (!active) return;
    constexpr double u = 0x1.0p-24;
    // 1 % over the bound covers the double test's own error and the
    // roundings of the bound's float evaluation.
    delta = static_cast<float>((3 * o + 8 * p) * u * 1.01) + kTiny;
    delta2 = 2 * delta;
    ox = static_cast<float>(ray.o[ray.kx]);
    oy = static_cast<float>(ray.o[ray.ky]);
    oz = static_cast<float>(ray.o[ray.kz]);
    sx = static_cast<float>(ray.sx);
    sy = static_cast<float>(ray.sy);
  }
};

/// Bit i set: triangle i of the packet may be hit (its edge functions do not
/// certainly disagree in sign); the exact test must decide. Kz: the ray's
/// kz (see WatertightRay).
template <int Kz>
inline uint32_t prefilterPacket(const PrefilterRay &ray, const TrianglePacket &packet) {
  if (!ray.active) return 0xf;
  constexpr int kx = (Kz + 1) % 3, ky = (Kz + 2) % 3;
  const __m128 signMask = _mm_set1_ps(-0.0f);
  const __m128 ox = _mm_set1_ps(ray.ox), oy = _mm_set1_ps(ray.oy), oz = _mm_set1_ps(ray.oz);
  const __m128 sx = _mm_set1_ps(ray.sx), sy = _mm_set1_ps(ray.sy);
  __m128 x[3], y[3], s[3];
  for (int c = 0; c < 3; ++c) {
    const __m128 az = _mm_sub_ps(_mm_load_ps(packet.v[c][Kz]), oz);
    x[c] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(packet.v[c][kx]), ox), _mm_mul_ps(sx, az));
    y[c] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(packet.v[c][ky]), oy), _mm_mul_ps(sy, az));
    s[c] = _mm_add_ps(_mm_andnot_ps(signMask, x[c]), _mm_andnot_ps(signMask, y[c]));
  }
  // Edge functions as in the double test (e0: edge p1-p2, e1: p2-p0, e2: p0-p1).
  const __m128 e0 = _mm_sub_ps(_mm_mul_ps(x[2], y[1]), _mm_mul_ps(y[2], x[1]));
  const __m128 e1 = _mm_sub_ps(_mm_mul_ps(x[0], y[2]), _mm_mul_ps(y[0], x[2]));
  const __m128 e2 = _mm_sub_ps(_mm_mul_ps(x[1], y[0]), _mm_mul_ps(y[1], x[0]));
  // One bound for the three edges, from the largest corner magnitude.
  const __m128 sMax = _mm_max_ps(s[0], _mm_max_ps(s[1], s[2]));
  const __m128 delta = _mm_set1_ps(ray.delta), delta2 = _mm_set1_ps(ray.delta2);
  const __m128 gamma = _mm_set1_ps(PrefilterRay::kGamma);
  const __m128 bound =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(delta2, _mm_add_ps(sMax, delta)),
                            _mm_mul_ps(gamma, _mm_mul_ps(sMax, sMax))),
                 _mm_set1_ps(PrefilterRay::kTiny));
  const __m128 negBound = _mm_xor_ps(bound, signMask);
  const __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, bound), _mm_cmpgt_ps(e1, bound)),
                               _mm_cmpgt_ps(e2, bound));
  const __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, negBound), _mm_cmplt_ps(e1, negBound)),
                               _mm_cmplt_ps(e2, negBound));
  return ~static_cast<uint32_t>(_mm_movemask_ps(_mm_and_ps(pos, neg))) & 0xfu;
}

/// Triangles in one packet.
constexpr uint32_t kPacketLanes = 4;

/// Bits 0 .. count-1 set (count <= 64): the lanes of a leaf of `count`
/// triangles.
inline uint64_t leafLanes(uint32_t count) {
  return count >= 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
}

/// prefilterPacket for the first `count` (1 to 64) triangles of consecutive
/// packets (bit i: triangle i), packet by packet: the SSE twin of
/// prefilterLeafAvx2.
template <int Kz>
inline uint64_t prefilterLeaf(const PrefilterRay &ray, const TrianglePacket *packets,
                              uint32_t count) {
  uint64_t lanes = 0;
  for (uint32_t p = 0; p * kPacketLanes < count; ++p)
    lanes |= uint64_t{prefilterPacket<Kz>(ray, packets[p])} << (p * kPacketLanes);
  return lanes & leafLanes(count);
}

/// prefilterPacket for the first `count` (1 to 64) triangles of consecutive
/// packets (bit i: triangle i), eight at a time with AVX2 in one call: call
/// only where cpuHasAvx2() (util/cpu_features.h).
template <int Kz>
uint64_t prefilterLeafAvx2(const PrefilterRay &ray, const TrianglePacket *packets,
                           uint32_t count);

} // namespace lray
