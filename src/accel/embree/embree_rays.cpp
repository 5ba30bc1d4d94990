#include "accel/embree/embree_rays.h"

#include "math/ray_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace lray {

namespace {

constexpr float kInfinityF = std::numeric_limits<float>::infinity();

/// The single-precision fields of `ray` (toRay1, and a lane of toRay8).
void toFloats(const Ray &ray, const Vec3 &origin, float &ox, float &oy, float &oz, float &dx,
              float &dy, float &dz, float &tnear, float &tfar) {
  ox = static_cast<float>(ray.o.x - origin.x);
  oy = static_cast<float>(ray.o.y - origin.y);
  oz = static_cast<float>(ray.o.z - origin.z);
  dx = static_cast<float>(ray.d.x);
  dy = static_cast<float>(ray.d.y);
  dz = static_cast<float>(ray.d.z);
  tnear = std::max(0.0f, roundDown(ray.tMin));
  tfar = roundUp(ray.tMax);
}

/// One lane of toRay8: what toRay1 writes, in lane `i` of `r`.
void toLane(const Ray &ray, const Vec3 &origin, RTCRay8 &r, unsigned i) {
  toFloats(ray, origin, r.org_x[i], r.org_y[i], r.org_z[i], r.dir_x[i], r.dir_y[i], r.dir_z[i],
           r.tnear[i], r.tfar[i]);
}

// Four rays at a time in vectors (math/ray_lanes.h): the same conversions
// lane by lane as toLane.
using lanes::Lanes;
using lanes::Mask;
using F4 = float __attribute__((vector_size(16)));

/// Lanes [at, at + 4) of `r` from rays[0, 4); false where a bound of the
/// valid interval is not a float, which toLane then rounds outwards.
[[gnu::always_inline]] inline bool toFourLanes(const Ray *rays, const Vec3 &origin, RTCRay8 &r,
                                                 unsigned at) {
  const Ray *const four[4] = {rays, rays + 1, rays + 2, rays + 3};
  lanes::RayLanes f;
  lanes::loadRays(four, f);
  auto put = [at](float *field, const Lanes &v) {
    const F4 narrow = __builtin_convertvector(v, F4);
    std::memcpy(field + at, &narrow, sizeof(F4));
  };
  put(r.org_x, f.ox - origin.x);
  put(r.org_y, f.oy - origin.y);
  put(r.org_z, f.oz - origin.z);
  put(r.dir_x, f.dx);
  put(r.dir_y, f.dy);
  put(r.dir_z, f.dz);
  const F4 tNear = __builtin_convertvector(f.tMin, F4);
  const F4 tFar = __builtin_convertvector(f.tMax, F4);
  const F4 zero = {};
  const F4 clamped = zero < tNear ? tNear : zero; // std::max(0.0f, t): NaN and -0 give 0
  std::memcpy(r.tnear + at, &clamped, sizeof(F4));
  std::memcpy(r.tfar + at, &tFar, sizeof(F4));
  const Mask inexact = (__builtin_convertvector(tNear, Lanes) > f.tMin) |
                       (__builtin_convertvector(tFar, Lanes) < f.tMax);
  return lanes::bits(inexact) == 0;
}

} // namespace

float roundDown(double x) {
  auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -kInfinityF) : f;
}

float roundUp(double x) {
  auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, kInfinityF) : f;
}

void toRay1(const Ray &ray, const Vec3 &origin, RTCRay &r) {
  toFloats(ray, origin, r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tnear, r.tfar);
  r.time = ray.time;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
}

void toRayHit1(const Ray &ray, const Vec3 &origin, RTCRayHit &rh) {
  toRay1(ray, origin, rh.ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void toRay8(const Ray *rays, size_t lanes, const Vec3 &origin, RTCRay8 &r, int *valid) {
  static constexpr int kValid[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  static constexpr unsigned kMask[8] = {~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};
  static constexpr unsigned kIds[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  std::memcpy(r.mask, kMask, sizeof kMask);
  std::memcpy(r.id, kIds, sizeof kIds);
  std::memset(r.flags, 0, sizeof r.flags);
  if (lanes == 8) {
    std::memcpy(valid, kValid, sizeof kValid);
    for (unsigned i = 0; i < 8; ++i) r.time[i] = rays[i].time;
  } else {
    for (unsigned i = 0; i < 8; ++i) {
      valid[i] = i < lanes ? -1 : 0;
      r.time[i] = rays[i < lanes ? i : 0].time;
    }
  }
  for (unsigned at = 0; at < 8; at += 4) {
    if (at + 4 <= lanes && toFourLanes(rays + at, origin, r, at)) continue;
    for (unsigned i = at; i < at + 4; ++i) toLane(rays[i < lanes ? i : 0], origin, r, i);
  }
}

void toRayHit8(const Ray *rays, size_t lanes, const Vec3 &origin, RTCRayHit8 &rh, int *valid,
               double *bestT) {
  toRay8(rays, lanes, origin, rh.ray, valid);
  for (unsigned i = 0; i < 8; ++i) {
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    bestT[i] = rays[i < lanes ? i : 0].tMax;
  }
}

} // namespace lray
