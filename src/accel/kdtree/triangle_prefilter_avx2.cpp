// Pipeline: acceleration (kd-tree backend). The prefilter of
// triangle_prefilter.h eight lanes wide (two packets) with AVX2, a whole
// leaf's packets per call (the ray's constants loaded once), compiled
// for AVX2 here only and called after a runtime check. Every lane performs
// the SSE version's operations in the same order, so the error bound holds
// as derived there. Only this file's own functions are compiled for AVX2
// (by attribute, one by one), so no inline function of a header gets an
// AVX2 copy that the linker might pick for other callers.
#include "accel/kdtree/triangle_prefilter.h"

#include <immintrin.h>

namespace lray {

// Every function below carries the target attribute (GCC and clang both
// honour it; clang ignores GCC's target pragma). Helpers rather than
// lambdas: a lambda would not inherit the target.
#define LRAY_AVX2 __attribute__((target("avx2")))

namespace {

LRAY_AVX2 __m256 loadPair(const TrianglePacket *packets, int c, int axis) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(packets[0].v[c][axis])),
                              _mm_load_ps(packets[1].v[c][axis]), 1);
}
// One packet's coordinates in the low four lanes (the high four unused).
LRAY_AVX2 __m256 loadOne(const TrianglePacket *packets, int c, int axis) {
  return _mm256_castps128_ps256(_mm_load_ps(packets[0].v[c][axis]));
}
LRAY_AVX2 __m256 bcast(const float &v) { return _mm256_broadcast_ss(&v); }
LRAY_AVX2 __m256 gt(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }

// The ray's constants in registers, loaded once per leaf.
struct RayLanes {
  __m256 ox, oy, oz, sx, sy, delta, delta2, gamma, tiny, signMask;
  LRAY_AVX2 explicit RayLanes(const PrefilterRay &ray)
      : ox(bcast(ray.ox)), oy(bcast(ray.oy)), oz(bcast(ray.oz)), sx(bcast(ray.sx)),
        sy(bcast(ray.sy)), delta(bcast(ray.delta)), delta2(bcast(ray.delta2)),
        gamma(_mm256_set1_ps(PrefilterRay::kGamma)), tiny(_mm256_set1_ps(PrefilterRay::kTiny)),
        signMask(_mm256_set1_ps(-0.0f)) {}
};

// The prefilter of eight triangles (two packets) or, with Width 4, of one
// packet in the low lanes.
template <int Kz, int Width>
LRAY_AVX2 uint32_t prefilterLanes(const RayLanes &r, const TrianglePacket *packets) {
  constexpr int kx = (Kz + 1) % 3, ky = (Kz + 2) % 3;
  __m256 x[3], y[3], s[3];
  for (int c = 0; c < 3; ++c) {
    const __m256 pz = Width == 8 ? loadPair(packets, c, Kz) : loadOne(packets, c, Kz);
    const __m256 px = Width == 8 ? loadPair(packets, c, kx) : loadOne(packets, c, kx);
    const __m256 py = Width == 8 ? loadPair(packets, c, ky) : loadOne(packets, c, ky);
    const __m256 az = _mm256_sub_ps(pz, r.oz);
    x[c] = _mm256_sub_ps(_mm256_sub_ps(px, r.ox), _mm256_mul_ps(r.sx, az));
    y[c] = _mm256_sub_ps(_mm256_sub_ps(py, r.oy), _mm256_mul_ps(r.sy, az));
    s[c] = _mm256_add_ps(_mm256_andnot_ps(r.signMask, x[c]), _mm256_andnot_ps(r.signMask, y[c]));
  }
  const __m256 e0 = _mm256_sub_ps(_mm256_mul_ps(x[2], y[1]), _mm256_mul_ps(y[2], x[1]));
  const __m256 e1 = _mm256_sub_ps(_mm256_mul_ps(x[0], y[2]), _mm256_mul_ps(y[0], x[2]));
  const __m256 e2 = _mm256_sub_ps(_mm256_mul_ps(x[1], y[0]), _mm256_mul_ps(y[1], x[0]));
  const __m256 sMax = _mm256_max_ps(s[0], _mm256_max_ps(s[1], s[2]));
  const __m256 bound =
      _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r.delta2, _mm256_add_ps(sMax, r.delta)),
                                  _mm256_mul_ps(r.gamma, _mm256_mul_ps(sMax, sMax))),
                    r.tiny);
  const __m256 negBound = _mm256_xor_ps(bound, r.signMask);
  const __m256 pos = _mm256_or_ps(_mm256_or_ps(gt(e0, bound), gt(e1, bound)), gt(e2, bound));
  const __m256 neg =
      _mm256_or_ps(_mm256_or_ps(gt(negBound, e0), gt(negBound, e1)), gt(negBound, e2));
  constexpr uint32_t kLanes = (1u << Width) - 1;
  return ~static_cast<uint32_t>(_mm256_movemask_ps(_mm256_and_ps(pos, neg))) & kLanes;
}

} // namespace

template <int Kz>
LRAY_AVX2 uint64_t prefilterLeafAvx2(const PrefilterRay &ray, const TrianglePacket *packets,
                                     uint32_t count) {
  const uint64_t all = leafLanes(count);
  if (!ray.active) return all;
  const RayLanes r(ray);
  uint64_t lanes = 0;
  uint32_t first = 0;
  for (; first + kPacketLanes < count; first += 2 * kPacketLanes, packets += 2)
    lanes |= uint64_t{prefilterLanes<Kz, 8>(r, packets)} << first;
  if (first < count) lanes |= uint64_t{prefilterLanes<Kz, 4>(r, packets)} << first;
  return lanes & all;
}

template uint64_t prefilterLeafAvx2<0>(const PrefilterRay &, const TrianglePacket *, uint32_t);
template uint64_t prefilterLeafAvx2<1>(const PrefilterRay &, const TrianglePacket *, uint32_t);
template uint64_t prefilterLeafAvx2<2>(const PrefilterRay &, const TrianglePacket *, uint32_t);

} // namespace lray
