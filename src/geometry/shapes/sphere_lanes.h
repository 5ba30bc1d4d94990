// Pipeline: geometry. Sphere's object-space test (sphere.h) for four rays
// at once, in the lanes of math/lanes.h: the origin shift of
// closestApproachShift (object_space.h), Sphere::intersect and its roots,
// with the scalar code's operations in the scalar code's order, lane by
// lane, so that each lane's hit and t are the scalar test's bit for bit. A
// camera packet's rays into a sphere are tested together (shape.cpp,
// intersectStillSphereLanes).
#pragma once

#include "geometry/shapes/object_space.h"
#include "geometry/shapes/sphere.h"
#include "math/lanes.h"
#include "math/ray_lanes.h"

#include <cstdint>
#include <cstring>

namespace lray::sphere_lanes {

using lanes::Lanes;
using lanes::Mask;
using lanes::RayLanes;

/// std::copysign(x, s) lane by lane.
[[gnu::always_inline]] inline Lanes copySign(const Lanes &x, const Lanes &s) {
  Mask xb, sb;
  std::memcpy(&xb, &x, sizeof x);
  std::memcpy(&sb, &s, sizeof s);
  const Mask sign = Mask{} + INT64_MIN;
  xb = (xb & ~sign) | (sb & sign);
  Lanes out;
  std::memcpy(&out, &xb, sizeof out);
  return out;
}

/// Sphere::missesLine of each lane's ray (object space, before the shift):
/// bit k set where the line of lane k passes the sphere by a clear margin,
/// so that intersect() finds no hit there either.
[[gnu::always_inline]] inline uint32_t missesLines(const RayLanes &r) {
  using namespace sphere_detail;
  const Lanes a = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz;
  const Lanes h = r.ox * r.dx + r.oy * r.dy + r.oz * r.dz;
  const Lanes oo = r.ox * r.ox + r.oy * r.oy + r.oz * r.oz;
  return lanes::bits((oo < kMaxPrefilteredOrigin * kMaxPrefilteredOrigin) &
                     (oo * a - h * h > a * (1 + kClearMargin) + 1e-12 * oo * a));
}

/// closestApproachShift(ray, {}, farOrigin) of each lane's ray.
[[gnu::always_inline]] inline Lanes originShift(const RayLanes &r, double farOrigin) {
  const Lanes ocx = 0.0 - r.ox, ocy = 0.0 - r.oy, ocz = 0.0 - r.oz;
  Lanes ax = ocx, ay = ocy, az = ocz;
  lanes::clearSigns(ax);
  lanes::clearSigns(ay);
  lanes::clearSigns(az);
  // maxAbsComponent: std::max(a, b) is (a < b) ? b : a.
  const Lanes yz = ay < az ? az : ay;
  const Lanes most = ax < yz ? yz : ax;
  const Lanes dd = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz;
  const Lanes along = (ocx * r.dx + ocy * r.dy + ocz * r.dz) / dd;
  const Lanes zero = Lanes{};
  const Lanes shift = dd > 0.0 ? along : zero;
  return most <= farOrigin ? zero : shift;
}

/// shape.cpp's reorigin of each lane's ray by its `shift` (none where 0).
[[gnu::always_inline]] inline void reorigin(RayLanes &r, const Lanes &shift) {
  const Mask keep = shift == 0.0;
  r.ox = keep ? r.ox : r.ox + r.dx * shift;
  r.oy = keep ? r.oy : r.oy + r.dy * shift;
  r.oz = keep ? r.oz : r.oz + r.dz * shift;
  r.tMin = keep ? r.tMin : r.tMin - shift;
  r.tMax = keep ? r.tMax : r.tMax - shift;
}

/// Sphere::intersect of each lane's ray (object space, shifted): bit k set
/// where lane k hits; its t in t[k] (other lanes' t are meaningless).
[[gnu::always_inline]] inline uint32_t intersect(const RayLanes &r, Lanes &t) {
  // sphere_detail::roots<true>.
  const Lanes a = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz;
  const Lanes h = r.ox * r.dx + r.oy * r.dy + r.oz * r.dz;
  const Lanes oo = r.ox * r.ox + r.oy * r.oy + r.oz * r.oz;
  Mask ok = a > 0.0;
  ok &= ~(oo * a - h * h > a * (1.0 + 1e-12 * (1.0 + oo)));
  ok &= ~((r.tMin >= 0.0) & (h > 0.0) & (oo - 1.0 > 0.0));
  const Lanes along = h / a;
  const Lanes vx = r.ox - r.dx * along, vy = r.oy - r.dy * along, vz = r.oz - r.dz * along;
  const Lanes disc = a * (1.0 - (vx * vx + vy * vy + vz * vz));
  ok &= ~(disc < 0.0);
  const Lanes c = oo - 1.0;
  // quadraticRoots.
  Lanes root = disc;
  lanes::sqrtInPlace(root);
  const Lanes q = -(h + copySign(root, h));
  const Mask doubleZero = q == 0.0;
  const Lanes zero = Lanes{};
  Lanes t0 = doubleZero ? zero : q / a, t1 = doubleZero ? zero : c / q;
  const Mask swap = t0 > t1;
  const Lanes lo = swap ? t1 : t0, hi = swap ? t0 : t1;
  // The nearest root in the open range (tMin, tMax).
  const Mask inLo = (lo > r.tMin) & (lo < r.tMax);
  const Mask inHi = (hi > r.tMin) & (hi < r.tMax);
  t = inLo ? lo : hi;
  return lanes::bits(ok & (inLo | inHi));
}

} // namespace lray::sphere_lanes
