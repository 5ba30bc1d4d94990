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

namespace {

/// Lane j as integrator_impl.h's light loop computes one point's sample:
/// the target (Light::Sampler::sample), its direction, spawnRayTo's ray
/// and phongColor.
void roundLane(LightLanes &s, const LightGrid &grid, size_t j) {
  s.valid[j] = 0;
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
void boundLanes(const LightLanes &s, LightRound &round) {
  for (size_t j = 0; j < s.count; ++j) {
    if (!s.valid[j]) continue;
    ++round.valid;
    const Vec3 o(s.ox[j], s.oy[j], s.oz[j]);
    const Vec3 end = o + Vec3(s.dx[j], s.dy[j], s.dz[j]);
    round.finite = round.finite && isFinite(o) && isFinite(end);
    round.from.extend(o);
    round.to.extend(end);
  }
}

LightRound roundScalar(LightLanes &s, const LightGrid &grid) {
  for (size_t j = 0; j < s.count; ++j) roundLane(s, grid, j);
  LightRound round;
  boundLanes(s, round);
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

/// The running boxes of the valid lanes' origins and ends (shaftEnds's),
/// and whether one of those was not finite.
struct BoundLanes4 {
  __m256d lo[6], hi[6]; ///< ox, oy, oz, then the ends'
  __m256d notFinite;
};

/// Lanes j..j+3 (some past count: they are made invalid).
LRAY_AVX2 inline void roundLanes4(LightLanes &s, const LightGrid &grid, size_t j,
                                  BoundLanes4 &bounds) {
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
      _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<int64_t>(s.count)), lane));
  const __m256d valid =
      _mm256_and_pd(inUse, _mm256_and_pd(_mm256_cmp_pd(dist, all(0), _CMP_GT_OQ),
                                         _mm256_cmp_pd(nl, all(0), _CMP_NLE_UQ)));
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
  const __m256d ends[6] = {ox, oy, oz, ox + dx, oy + dy, oz + dz};
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  for (int k = 0; k < 6; ++k) {
    bounds.lo[k] = select(valid, _mm256_min_pd(bounds.lo[k], ends[k]), bounds.lo[k]);
    bounds.hi[k] = select(valid, _mm256_max_pd(bounds.hi[k], ends[k]), bounds.hi[k]);
    const __m256d finite = _mm256_cmp_pd(_mm256_and_pd(ends[k], magnitude),
                                         all(std::numeric_limits<double>::max()), _CMP_LE_OQ);
    bounds.notFinite = _mm256_or_pd(bounds.notFinite, _mm256_andnot_pd(finite, valid));
  }

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

/// Every lane, then phongColor's std::pow lane by lane where the exponent
/// is no small integer (c += specular * power).
LRAY_AVX2 void roundAvx2(LightLanes &s, const LightGrid &grid, LightRound &round) {
  BoundLanes4 bounds;
  for (int k = 0; k < 6; ++k) {
    bounds.lo[k] = all(std::numeric_limits<double>::infinity());
    bounds.hi[k] = all(-std::numeric_limits<double>::infinity());
  }
  bounds.notFinite = _mm256_setzero_pd();
  for (size_t j = 0; j < s.count; j += 4) roundLanes4(s, grid, j, bounds);
  for (size_t j = 0; j < s.count; ++j) {
    round.valid += s.valid[j];
    if (!s.valid[j] || s.exponent[j] >= 0 || s.specular[j] == 0) continue;
    const double highlight = s.specular[j] * specularPower(s.rv[j], *s.material[j]);
    s.cr[j] += highlight, s.cg[j] += highlight, s.cb[j] += highlight;
  }
  alignas(32) double lo[6][4], hi[6][4];
  for (int k = 0; k < 6; ++k) {
    _mm256_store_pd(lo[k], bounds.lo[k]);
    _mm256_store_pd(hi[k], bounds.hi[k]);
  }
  round.finite = _mm256_movemask_pd(bounds.notFinite) == 0;
  // The caller's SSE code would otherwise run with the upper halves dirty
  // (GCC left them so on one path out, and every SSE instruction after it
  // paid for that, through the rest of the render).
  _mm256_zeroupper();
  double box[2][6];
  for (int k = 0; k < 6; ++k) {
    box[0][k] = std::min(std::min(lo[k][0], lo[k][1]), std::min(lo[k][2], lo[k][3]));
    box[1][k] = std::max(std::max(hi[k][0], hi[k][1]), std::max(hi[k][2], hi[k][3]));
  }
  round.from = {{box[0][0], box[0][1], box[0][2]}, {box[1][0], box[1][1], box[1][2]}};
  round.to = {{box[0][3], box[0][4], box[0][5]}, {box[1][3], box[1][4], box[1][5]}};
}

/// sums += lightColor * c in each lane where add[j] (4 lanes at a time).
LRAY_AVX2 void addLitAvx2(LightLanes &s, const Color &lightColor, const uint8_t *add) {
  const __m256d lr = all(lightColor.r), lg = all(lightColor.g), lb = all(lightColor.b);
  for (size_t j = 0; j < s.count; j += 4) {
    int32_t bytes;
    std::memcpy(&bytes, add + j, sizeof bytes);
    const __m256d on = _mm256_castsi256_pd(_mm256_cmpgt_epi64(
        _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(bytes)), _mm256_setzero_si256()));
    put(s.sr, j, select(on, at(s.sr, j) + lr * at(s.cr, j), at(s.sr, j)));
    put(s.sg, j, select(on, at(s.sg, j) + lg * at(s.cg, j), at(s.sg, j)));
    put(s.sb, j, select(on, at(s.sb, j) + lb * at(s.cb, j), at(s.sb, j)));
  }
  _mm256_zeroupper();
}

} // namespace

namespace detail {
LightRound lightLanesRound(LightLanes &lanes, const LightGrid &grid, bool avx2) {
  if (!avx2) return roundScalar(lanes, grid);
  LightRound round;
  roundAvx2(lanes, grid, round);
  return round;
}

void addLit(LightLanes &lanes, const Color &lightColor, const uint8_t *add, bool avx2) {
  if (avx2) return addLitAvx2(lanes, lightColor, add);
  for (size_t j = 0; j < lanes.count; ++j) {
    if (!add[j]) continue;
    const Color lit = lightColor * Color(lanes.cr[j], lanes.cg[j], lanes.cb[j]);
    lanes.sr[j] += lit.r, lanes.sg[j] += lit.g, lanes.sb[j] += lit.b;
  }
}
} // namespace detail

LightRound lightLanesRound(LightLanes &lanes, const LightGrid &grid) {
  return detail::lightLanesRound(lanes, grid, cpuHasAvx2());
}

void addLit(LightLanes &lanes, const Color &lightColor, const uint8_t *add) {
  detail::addLit(lanes, lightColor, add, cpuHasAvx2());
}

} // namespace lray
