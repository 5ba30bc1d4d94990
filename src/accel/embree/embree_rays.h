// Pipeline: acceleration (Embree backend). The caller's double rays as
// Embree's single-precision ones: the origin relative to the float frame's
// origin (geometry/float_frame.h; t is the same in both frames), and the
// valid interval rounded outwards, so that Embree's culling never drops
// what the double test accepts.
#pragma once

#include "math/ray.h"

#include <embree3/rtcore.h>

#include <cstddef>

namespace lray {

/// The largest float at most `x`, and the smallest at least `x`.
float roundDown(double x);
float roundUp(double x);

/// `ray` as Embree's single ray, in the float frame about `origin`.
void toRay1(const Ray &ray, const Vec3 &origin, RTCRay &r);
/// `ray` as Embree's single ray with a hit record (toRay1), no hit yet.
void toRayHit1(const Ray &ray, const Vec3 &origin, RTCRayHit &rh);
/// rays[0, lanes) as an 8-wide packet (lanes beyond repeat ray 0, invalid),
/// ray IDs their lane numbers.
void toRay8(const Ray *rays, size_t lanes, const Vec3 &origin, RTCRay8 &r, int *valid);
/// toRay8 with hit records, no hit yet; bestT[i] = the ray's tMax.
void toRayHit8(const Ray *rays, size_t lanes, const Vec3 &origin, RTCRayHit8 &rh, int *valid,
               double *bestT);

} // namespace lray
