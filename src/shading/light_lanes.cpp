// Pipeline: shading. lightLanesRound (light_lanes.h): one lane at a time
// with the integrator's own formulas, and the same arithmetic in four
// double AVX2 lanes (no fused multiply-add, so each product and sum
// rounds as the scalar path's does).
#include "shading/light_lanes.h"

#include "util/cpu_features.h"

#include <immintrin.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace lray {

void LightLanes::add(uint32_t index, const Hit &hit, const SpawnOrigins &origins, const Vec3 &n,
                     const Vec3 &v, const Color &pigment, const Material &m) {
  const size_t j = count++;
  point[j] = index;
  material[j] = &m;
  time[j] = hit.time;
  px[j] = hit.p.x, py[j] = hit.p.y, pz[j] = hit.p.z;
  nx[j] = n.x, ny[j] = n.y, nz[j] = n.z;
  gx[j] = hit.ng.x, gy[j] = hit.ng.y, gz[j] = hit.ng.z;
  vx[j] = v.x, vy[j] = v.y, vz[j] = v.z;
  fx[j] = origins.front.x, fy[j] = origins.front.y, fz[j] = origins.front.z;
  bx[j] = origins.back.x, by[j] = origins.back.y, bz[j] = origins.back.z;
  const Color diffuse = pigment * m.finish.diffuse;
  dr[j] = diffuse.r, dg[j] = diffuse.g, db[j] = diffuse.b;
  specular[j] = m.finish.specular;
  exponent[j] = m.integerExponent;
  if (m.finish.specular != 0)
    while (powerBits < 31 && (m.integerExponent >> powerBits) > 0) ++powerBits;
}

size_t LightLanes::writeRays(LaneSpan span, Ray *rays, size_t first) {
  size_t n = first;
  for (size_t j = span.begin; j < span.end; ++j) {
    if (!valid[j]) continue;
    Ray &ray = rays[n]; // field by field: see spawnRayTo
    ray.o = {ox[j], oy[j], oz[j]};
    ray.d = {dx[j], dy[j], dz[j]};
    ray.tMin = 0;
    ray.tMax = 1;
    ray.time = time[j];
    rayLane[n++] = static_cast<uint32_t>(j);
  }
  return n - first;
}

namespace {

/// Lane j as integrator_impl.h's light loop computes one point's sample:
/// the target (Light::Sampler::sample), its direction, spawnRayTo's ray
/// and phongColor.
void roundLane(LightLanes &s, const LightGrid &grid, size_t j) {
  s.valid[j] = 0;
  if (!s.active[j]) return;
  const Vec3 target = grid.corner + grid.cellX * s.ax[j] + grid.cellZ * s.az[j];
  const Vec3 toLight = target - Vec3(s.px[j], s.py[j], s.pz[j]);
  const double dist = length(toLight);
  if (!(dist > 0)) return;
  const Vec3 l = toLight / dist;
  const Vec3 n(s.nx[j], s.ny[j], s.nz[j]);
  const double nl = dot(n, l);
  if (nl <= 0) return; // faces away: no shadow ray
  s.valid[j] = 1;
  const bool back = dot(toLight, Vec3(s.gx[j], s.gy[j], s.gz[j])) < 0;
  const Vec3 o = back ? Vec3(s.bx[j], s.by[j], s.bz[j]) : Vec3(s.fx[j], s.fy[j], s.fz[j]);
  const Vec3 d = target - o;
  s.ox[j] = o.x, s.oy[j] = o.y, s.oz[j] = o.z;
  s.dx[j] = d.x, s.dy[j] = d.y, s.dz[j] = d.z;
  const Color c = phongColor(n, Vec3(s.vx[j], s.vy[j], s.vz[j]), l, nl,
                             Color(s.dr[j], s.dg[j], s.db[j]), *s.material[j]);
  s.cr[j] = c.r, s.cg[j] = c.g, s.cb[j] = c.b;
}

/// The boxes around the valid lanes' origins and ends, in lane order.
void boundLanes(const LightLanes &s, LaneSpan span, LightRound &round) {
  for (size_t j = span.begin; j < span.end; ++j) {
    if (!s.valid[j]) continue;
    ++round.valid;
    const Vec3 o(s.ox[j], s.oy[j], s.oz[j]);
    const Vec3 end = o + Vec3(s.dx[j], s.dy[j], s.dz[j]);
    round.finite = round.finite && isFinite(o) && isFinite(end);
    round.from.extend(o);
    round.to.extend(end);
  }
}

LightRound roundScalar(LightLanes &s, LaneSpan span, const LightGrid &grid) {
  for (size_t j = span.begin; j < span.end; ++j) roundLane(s, grid, j);
  LightRound round;
  boundLanes(s, span, round);
  return round;
}

#define LRAY_AVX2 __attribute__((target("avx2")))

LRAY_AVX2 inline __m256d all(double x) { return _mm256_set1_pd(x); }

/// lray::dot in each lane, left to right.
LRAY_AVX2 inline __m256d dot(__m256d ax, __m256d ay, __m256d az, __m256d bx, __m256d by,
                             __m256d bz) {
  return ax * bx + ay * by + az * bz;
}

LRAY_AVX2 inline __m256d at(const double *a, size_t j) { return _mm256_load_pd(a + j); }
LRAY_AVX2 inline void put(double *a, size_t j, __m256d v) { _mm256_store_pd(a + j, v); }

LRAY_AVX2 inline __m256d select(__m256d mask, __m256d ifTrue, __m256d ifFalse) {
  return _mm256_blendv_pd(ifFalse, ifTrue, mask);
}

/// The lanes among j..j+3 whose flag is not 0, as a mask.
LRAY_AVX2 inline __m256d flagged(const uint8_t *flags, size_t j) {
  int32_t bytes;
  std::memcpy(&bytes, flags + j, sizeof bytes);
  return _mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_cvtepu8_epi64(_mm_cvtsi32_si128(bytes)),
                                                _mm256_setzero_si256()));
}

/// Lanes j..j+3 (some at or past `end`: they are made invalid).
LRAY_AVX2 inline void roundLanes4(LightLanes &s, const LightGrid &grid, size_t j, size_t end) {
  const __m256d ax = at(s.ax, j), az = at(s.az, j);
  const __m256d tx = all(grid.corner.x) + all(grid.cellX.x) * ax + all(grid.cellZ.x) * az;
  const __m256d ty = all(grid.corner.y) + all(grid.cellX.y) * ax + all(grid.cellZ.y) * az;
  const __m256d tz = all(grid.corner.z) + all(grid.cellX.z) * ax + all(grid.cellZ.z) * az;
  const __m256d lx0 = tx - at(s.px, j), ly0 = ty - at(s.py, j), lz0 = tz - at(s.pz, j);
  const __m256d dist = _mm256_sqrt_pd(dot(lx0, ly0, lz0, lx0, ly0, lz0));
  const __m256d lx = lx0 / dist, ly = ly0 / dist, lz = lz0 / dist;
  const __m256d nx = at(s.nx, j), ny = at(s.ny, j), nz = at(s.nz, j);
  const __m256d nl = dot(nx, ny, nz, lx, ly, lz);
  const __m256i lane = _mm256_add_epi64(_mm256_set1_epi64x(static_cast<int64_t>(j)),
                                        _mm256_setr_epi64x(0, 1, 2, 3));
  const __m256d inUse = _mm256_castsi256_pd(
      _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<int64_t>(end)), lane));
  const __m256d facing = _mm256_and_pd(_mm256_cmp_pd(dist, all(0), _CMP_GT_OQ),
                                       _mm256_cmp_pd(nl, all(0), _CMP_NLE_UQ));
  const __m256d valid = _mm256_and_pd(_mm256_and_pd(inUse, flagged(s.active, j)), facing);
  const int validBits = _mm256_movemask_pd(valid);
  for (int k = 0; k < 4; ++k) s.valid[j + k] = (validBits >> k) & 1;
  if (validBits == 0) return;

  const __m256d back = _mm256_cmp_pd(dot(lx0, ly0, lz0, at(s.gx, j), at(s.gy, j), at(s.gz, j)),
                                     all(0), _CMP_LT_OQ);
  const __m256d ox = select(back, at(s.bx, j), at(s.fx, j));
  const __m256d oy = select(back, at(s.by, j), at(s.fy, j));
  const __m256d oz = select(back, at(s.bz, j), at(s.fz, j));
  const __m256d dx = tx - ox, dy = ty - oy, dz = tz - oz;
  put(s.ox, j, ox), put(s.oy, j, oy), put(s.oz, j, oz);
  put(s.dx, j, dx), put(s.dy, j, dy), put(s.dz, j, dz);

  // phongColor: diffuse N.L, plus specular * specularPower(R.V) where
  // the specular is not 0.
  __m256d cr = at(s.dr, j) * nl, cg = at(s.dg, j) * nl, cb = at(s.db, j) * nl;
  const __m256d specular = at(s.specular, j);
  const __m256d hasSpecular = _mm256_cmp_pd(specular, all(0), _CMP_NEQ_UQ);
  if (_mm256_movemask_pd(hasSpecular) != 0) {
    const __m256d twoNl = all(2) * nl;
    const __m256d rv = dot(nx * twoNl - lx, ny * twoNl - ly, nz * twoNl - lz, at(s.vx, j),
                           at(s.vy, j), at(s.vz, j));
    put(s.rv, j, rv);
    // specularPower's squaring, bit by bit of the exponent (at most 64).
    const __m256i e = _mm256_cvtepi32_epi64(
        _mm_load_si128(reinterpret_cast<const __m128i *>(s.exponent + j)));
    __m256d power = all(1), x = rv;
    for (int bit = 0; bit < s.powerBits; ++bit) {
      const __m256i b = _mm256_set1_epi64x(int64_t{1} << bit);
      const __m256d set = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(e, b), b));
      power = select(set, power * x, power);
      x = x * x;
    }
    const __m256d zeroExponent = _mm256_castsi256_pd(_mm256_cmpeq_epi64(e, _mm256_setzero_si256()));
    power = select(_mm256_cmp_pd(rv, all(0), _CMP_GT_OQ), power,
                   select(zeroExponent, all(1), all(0)));
    // Lanes with a non-integer exponent are finished with std::pow after.
    const __m256d integer = _mm256_castsi256_pd(_mm256_cmpgt_epi64(e, _mm256_set1_epi64x(-1)));
    const __m256d s3 = specular * power;
    const __m256d add = _mm256_and_pd(hasSpecular, integer);
    cr = select(add, cr + s3, cr), cg = select(add, cg + s3, cg), cb = select(add, cb + s3, cb);
  }
  put(s.cr, j, cr), put(s.cg, j, cg), put(s.cb, j, cb);
}

/// One axis of the boxes around the valid lanes' origins (o = o[]) and
/// ends (o + d): lo and hi of each, reduced over the lanes. `finite`
/// turns false where a valid value is not finite.
LRAY_AVX2 void boundAxis(const LightLanes &s, LaneSpan span, const double *o, const double *d,
                         double (&lo)[2], double (&hi)[2], bool &finite) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  __m256d oLo = all(inf), oHi = all(-inf), eLo = all(inf), eHi = all(-inf);
  __m256d notFinite = _mm256_setzero_pd();
  for (size_t j = span.begin; j < span.end; j += 4) {
    const __m256d valid = flagged(s.valid, j);
    const __m256d origin = at(o, j), end = origin + at(d, j);
    oLo = select(valid, _mm256_min_pd(oLo, origin), oLo);
    oHi = select(valid, _mm256_max_pd(oHi, origin), oHi);
    eLo = select(valid, _mm256_min_pd(eLo, end), eLo);
    eHi = select(valid, _mm256_max_pd(eHi, end), eHi);
    for (__m256d v : {origin, end}) {
      const __m256d ok = _mm256_cmp_pd(_mm256_and_pd(v, magnitude),
                                       all(std::numeric_limits<double>::max()), _CMP_LE_OQ);
      notFinite = _mm256_or_pd(notFinite, _mm256_andnot_pd(ok, valid));
    }
  }
  alignas(32) double lanes[4][4];
  _mm256_store_pd(lanes[0], oLo), _mm256_store_pd(lanes[1], oHi);
  _mm256_store_pd(lanes[2], eLo), _mm256_store_pd(lanes[3], eHi);
  finite = finite && _mm256_movemask_pd(notFinite) == 0;
  for (int k = 0; k < 2; ++k) {
    const double *l = lanes[2 * k], *h = lanes[2 * k + 1];
    lo[k] = std::min(std::min(l[0], l[1]), std::min(l[2], l[3]));
    hi[k] = std::max(std::max(h[0], h[1]), std::max(h[2], h[3]));
  }
}

/// Every lane, then phongColor's std::pow lane by lane where the exponent
/// is no small integer (c += specular * power), then the boxes.
LRAY_AVX2 void roundAvx2(LightLanes &s, LaneSpan span, const LightGrid &grid, LightRound &round) {
  for (size_t j = span.begin; j < span.end; j += 4) roundLanes4(s, grid, j, span.end);
  for (size_t j = span.begin; j < span.end; ++j) {
    round.valid += s.valid[j];
    if (!s.valid[j] || s.exponent[j] >= 0 || s.specular[j] == 0) continue;
    const double highlight = s.specular[j] * specularPower(s.rv[j], *s.material[j]);
    s.cr[j] += highlight, s.cg[j] += highlight, s.cb[j] += highlight;
  }
  if (round.valid > 0) {
    double lo[3][2], hi[3][2]; // per axis: origins, ends
    boundAxis(s, span, s.ox, s.dx, lo[0], hi[0], round.finite);
    boundAxis(s, span, s.oy, s.dy, lo[1], hi[1], round.finite);
    boundAxis(s, span, s.oz, s.dz, lo[2], hi[2], round.finite);
    round.from = {{lo[0][0], lo[1][0], lo[2][0]}, {hi[0][0], hi[1][0], hi[2][0]}};
    round.to = {{lo[0][1], lo[1][1], lo[2][1]}, {hi[0][1], hi[1][1], hi[2][1]}};
  }
  // The caller's SSE code would otherwise run with the upper halves dirty
  // (GCC left them so on one path out, and every SSE instruction after it
  // paid for that, through the rest of the render).
  _mm256_zeroupper();
}

/// sums += lightColor * c in each lane where add[j] (4 lanes at a time).
LRAY_AVX2 void addLitAvx2(LightLanes &s, LaneSpan span, const LitColours &c,
                          const Color &lightColor, double weight, const uint8_t *add) {
  const __m256d lr = all(lightColor.r), lg = all(lightColor.g), lb = all(lightColor.b);
  const __m256d w = all(weight);
  for (size_t j = span.begin; j < span.end; j += 4) {
    const __m256d on = flagged(add, j);
    put(s.sr, j, select(on, at(s.sr, j) + lr * at(c.r, j) * w, at(s.sr, j)));
    put(s.sg, j, select(on, at(s.sg, j) + lg * at(c.g, j) * w, at(s.sg, j)));
    put(s.sb, j, select(on, at(s.sb, j) + lb * at(c.b, j) * w, at(s.sb, j)));
  }
  _mm256_zeroupper();
}

/// 64-bit products' low halves in each lane: one instruction where the
/// build targets AVX-512 (LRAY_NATIVE, README.md "Building"); AVX2 alone
/// multiplies 32 bits, so three products and their sum.
LRAY_AVX2 inline __m256i mul64(__m256i a, __m256i b) {
#if defined(__AVX512DQ__) && defined(__AVX512VL__)
  return _mm256_mullo_epi64(a, b);
#else
  const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(a, _mm256_srli_epi64(b, 32)),
                                         _mm256_mul_epu32(_mm256_srli_epi64(a, 32), b));
  return _mm256_add_epi64(_mm256_mul_epu32(a, b), _mm256_slli_epi64(cross, 32));
#endif
}

/// Sampler::independent(key, dim) in each lane: mix64, then the top 53
/// bits converted exactly (by AVX-512's conversion, or as two halves, each
/// by the 2^52 exponent trick) and scaled by 2^-53.
LRAY_AVX2 inline __m256d independentLanes(__m256i key, __m256i dim) {
  const __m256i golden = _mm256_set1_epi64x(static_cast<int64_t>(0x9e3779b97f4a7c15ULL));
  __m256i z = _mm256_add_epi64(key, mul64(golden, dim));
  z = mul64(_mm256_xor_si256(z, _mm256_srli_epi64(z, 30)),
            _mm256_set1_epi64x(static_cast<int64_t>(0xbf58476d1ce4e5b9ULL)));
  z = mul64(_mm256_xor_si256(z, _mm256_srli_epi64(z, 27)),
            _mm256_set1_epi64x(static_cast<int64_t>(0x94d049bb133111ebULL)));
  z = _mm256_srli_epi64(_mm256_xor_si256(z, _mm256_srli_epi64(z, 31)), 11);
#if defined(__AVX512DQ__) && defined(__AVX512VL__)
  return _mm256_cvtepu64_pd(z) * all(0x1p-53); // exact: z < 2^53
#else
  const __m256i lo = _mm256_blend_epi32(z, _mm256_set1_epi64x(0x4330000000000000LL), 0xaa);
  const __m256i hi = _mm256_or_si256(_mm256_srli_epi64(z, 32),
                                     _mm256_set1_epi64x(0x4530000000000000LL));
  const __m256d value = (_mm256_castsi256_pd(hi) - all(0x1p84 + 0x1p52)) + _mm256_castsi256_pd(lo);
  return value * all(0x1p-53);
#endif
}

/// The jitter of the active lanes in `span`, added to the cell each lane
/// holds in ax, az (its column and row).
LRAY_AVX2 void placeAvx2(LightLanes &s, LaneSpan span) {
  const __m256i one = _mm256_set1_epi64x(1), two = _mm256_set1_epi64x(2);
  for (size_t j = span.begin; j < span.end; j += 4) {
    const __m256i key = _mm256_load_si256(reinterpret_cast<const __m256i *>(s.key + j));
    const __m256i drawn = _mm256_load_si256(reinterpret_cast<const __m256i *>(s.drawn + j));
    put(s.ax, j, at(s.ax, j) + independentLanes(key, _mm256_add_epi64(drawn, one)));
    put(s.az, j, at(s.az, j) + independentLanes(key, _mm256_add_epi64(drawn, two)));
    const __m256i active = _mm256_castpd_si256(flagged(s.active, j));
    _mm256_store_si256(reinterpret_cast<__m256i *>(s.drawn + j),
                       _mm256_add_epi64(drawn, _mm256_and_si256(active, two)));
  }
  _mm256_zeroupper();
}

/// placeAvx2 one lane at a time.
void placeScalar(LightLanes &s, LaneSpan span) {
  for (size_t j = span.begin; j < span.end; ++j) {
    if (!s.active[j]) continue;
    const uint64_t drawn = s.drawn[j];
    s.ax[j] += Sampler::independent(s.key[j], drawn + 1);
    s.az[j] += Sampler::independent(s.key[j], drawn + 2);
    s.drawn[j] = drawn + 2;
  }
}

} // namespace

bool loadSamplers(LightLanes &lanes, const Sampler *samplers) {
  for (size_t j = 0; j < lanes.count; ++j) {
    const Sampler &sampler = samplers[lanes.point[j]];
    if (sampler.stratified()) return false;
    lanes.key[j] = sampler.key();
    lanes.drawn[j] = sampler.drawn();
  }
  return true;
}

void storeSamplers(const LightLanes &lanes, Sampler *samplers) {
  for (size_t j = 0; j < lanes.count; ++j) {
    Sampler &sampler = samplers[lanes.point[j]];
    sampler.advance(lanes.drawn[j] - sampler.drawn());
  }
}

namespace detail {
void placeLanes(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int row, int col,
                bool avx2) {
  std::fill(lanes.active + span.begin, lanes.active + span.end, uint8_t{1});
  // Light::Sampler::place: the cell's centre, or its corner plus a jitter.
  const double centre = light.area() ? 0 : 0.5;
  std::fill(lanes.ax + span.begin, lanes.ax + span.end, col + centre);
  std::fill(lanes.az + span.begin, lanes.az + span.end, row + centre);
  if (!light.area()) return;
  if (avx2) return placeAvx2(lanes, span);
  placeScalar(lanes, span);
}

void placeSpread(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int round,
                 int shares, Sampler *samplers, bool inLanes, bool avx2) {
  const int cells = light.sampleCount();
  for (size_t j = span.begin; j < span.end; ++j) {
    Sampler &sampler = samplers[lanes.point[j]];
    const int k = round * shares + static_cast<int>(sampler.lightStratum % shares);
    lanes.active[j] = k < cells;
    if (!lanes.active[j]) continue;
    const int row = k / light.cols(), col = k % light.cols();
    if (!inLanes) {
      light.place(row, col, sampler, lanes.ax[j], lanes.az[j]);
      continue;
    }
    const double centre = light.area() ? 0 : 0.5;
    lanes.ax[j] = col + centre;
    lanes.az[j] = row + centre;
  }
  if (!inLanes || !light.area()) return;
  if (avx2) return placeAvx2(lanes, span);
  placeScalar(lanes, span);
}

LightRound lightLanesRound(LightLanes &lanes, LaneSpan span, const LightGrid &grid, bool avx2) {
  if (!avx2) return roundScalar(lanes, span, grid);
  LightRound round;
  roundAvx2(lanes, span, grid, round);
  return round;
}

void addLit(LightLanes &lanes, LaneSpan span, const LitColours &c, const Color &lightColor,
            double weight, const uint8_t *add, bool avx2) {
  if (avx2) return addLitAvx2(lanes, span, c, lightColor, weight, add);
  for (size_t j = span.begin; j < span.end; ++j) {
    if (!add[j]) continue;
    const Color lit = lightColor * Color(c.r[j], c.g[j], c.b[j]) * weight;
    lanes.sr[j] += lit.r, lanes.sg[j] += lit.g, lanes.sb[j] += lit.b;
  }
}
} // namespace detail

LightRound lightLanesRound(LightLanes &lanes, LaneSpan span, const LightGrid &grid) {
  return detail::lightLanesRound(lanes, span, grid, cpuHasAvx2());
}

void addLit(LightLanes &lanes, LaneSpan span, const LitColours &c, const Color &lightColor,
            double weight, const uint8_t *add) {
  detail::addLit(lanes, span, c, lightColor, weight, add, cpuHasAvx2());
}

void placeSpread(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int round,
                 int shares, Sampler *samplers, bool inLanes) {
  detail::placeSpread(lanes, span, light, round, shares, samplers, inLanes, cpuHasAvx2());
}

void placeLanes(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int row, int col) {
  detail::placeLanes(lanes, span, light, row, col, cpuHasAvx2());
}

} // namespace lray
