// Pipeline: acceleration (kd-tree backend). The watertight ray/triangle test
// of Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection"
// (JCGT 2(1)): the ray is made the +z axis of a sheared, permuted frame, so
// each triangle edge's 2-D edge function depends only on the edge's two
// vertices and the ray. Neighbouring triangles then agree exactly on which
// side of a shared edge the ray passes: no ray slips between them.
#pragma once

#include "math/ray.h"
#include "math/vec3.h"

#include <cmath>

namespace lray {

/// A ray prepared for the watertight test: the axis along which it moves
/// most becomes z (kz), kx and ky follow cyclically; (sx, sy, sz) shear the
/// ray direction onto (0, 0, 1), so a vertex v relative to the origin maps
/// to (v[kx] - sx v[kz], v[ky] - sy v[kz], sz v[kz]). (The paper swaps kx
/// and ky for rays along -kz to keep the winding; that only negates all
/// three edge functions exactly, and both facings are hit here, so t and
/// the barycentrics are the same without it.)
struct WatertightRay {
  double o[3];
  int kx, ky, kz;
  double sx, sy, sz;
  double tMin = 0;

  explicit WatertightRay(const Ray &ray) : o{ray.o.x, ray.o.y, ray.o.z}, tMin(ray.tMin) {
    Vec3 ad = abs(ray.d);
    kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    sx = ray.d[kx] / ray.d[kz];
    sy = ray.d[ky] / ray.d[kz];
    sz = 1.0 / ray.d[kz];
  }
};

/// Ray parameter and barycentrics of corners 1 and 2 (corner 0 has 1 - b1 - b2).
struct TriangleHitParams {
  double t = 0, b1 = 0, b2 = 0;
};

/// The end of the test for a triangle whose edge functions e0, e1, e2 agree
/// in sign; akz, bkz, ckz are its corners' kz components relative to the
/// ray origin.
inline bool finishTriangle(const WatertightRay &ray, double e0, double e1, double e2, double akz,
                           double bkz, double ckz, double tMax, TriangleHitParams &out) {
  const double det = e0 + e1 + e2;
  if (det == 0) return false;
  // Scaled hit distance, compared before dividing.
  const double az = ray.sz * akz, bz = ray.sz * bkz, cz = ray.sz * ckz;
  const double tScaled = e0 * az + e1 * bz + e2 * cz;
  const double invDet = 1.0 / det;
  const double t = tScaled * invDet;
  if (!(t > ray.tMin && t < tMax)) return false;
  out.t = t;
  out.b1 = e1 * invDet;
  out.b2 = e2 * invDet;
  return true;
}

namespace detail {

/// The test with the ray's axis kz known at compile time (the permutation
/// then costs nothing); `ray.kz` must equal Kz.
template <int Kz, class Point>
inline bool intersectTriangleCorners(const WatertightRay &ray, const Point &p0, const Point &p1,
                                     const Point &p2, double tMax, TriangleHitParams &out) {
  // Vertices relative to the origin, then sheared so the ray runs along +z.
  const double a[3] = {p0.x - ray.o[0], p0.y - ray.o[1], p0.z - ray.o[2]};
  const double b[3] = {p1.x - ray.o[0], p1.y - ray.o[1], p1.z - ray.o[2]};
  const double c[3] = {p2.x - ray.o[0], p2.y - ray.o[1], p2.z - ray.o[2]};
  constexpr int kz = Kz, kx = (Kz + 1) % 3, ky = (Kz + 2) % 3;
  const double ax = a[kx] - ray.sx * a[kz], ay = a[ky] - ray.sy * a[kz];
  const double bx = b[kx] - ray.sx * b[kz], by = b[ky] - ray.sy * b[kz];
  const double cx = c[kx] - ray.sx * c[kz], cy = c[ky] - ray.sy * c[kz];

  // Edge functions: e0 for edge p1-p2 (weight of p0), e1 for p2-p0, e2 for p0-p1.
  double e0 = cx * by - cy * bx;
  double e1 = ax * cy - ay * cx;
  double e2 = bx * ay - by * ax;
  // A zero edge function leaves the ray on the edge: recompute it in wider
  // precision, as the paper falls back from float to double. Only the zero
  // ones, so the value of a shared edge never depends on the other edges and
  // both neighbours compute exactly opposite signs.
  using Wide = long double;
  if (e0 == 0) e0 = static_cast<double>(Wide(cx) * Wide(by) - Wide(cy) * Wide(bx));
  if (e1 == 0) e1 = static_cast<double>(Wide(ax) * Wide(cy) - Wide(ay) * Wide(cx));
  if (e2 == 0) e2 = static_cast<double>(Wide(bx) * Wide(ay) - Wide(by) * Wide(ax));
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  return finishTriangle(ray, e0, e1, e2, a[kz], b[kz], c[kz], tMax, out);
}

template <int K> inline float component(const Vec3f &v) {
  if constexpr (K == 0) return v.x;
  else if constexpr (K == 1) return v.y;
  else return v.z;
}

} // namespace detail

/// Watertight intersection of the ray with triangle (p0, p1, p2), both in the
/// same space, for t in (ray.tMin, tMax). Either facing is hit; a triangle
/// seen exactly edge-on is missed.
inline bool intersectTriangle(const WatertightRay &ray, const Vec3 &p0, const Vec3 &p1,
                              const Vec3 &p2, double tMax, TriangleHitParams &out) {
  switch (ray.kz) {
  case 0: return detail::intersectTriangleCorners<0>(ray, p0, p1, p2, tMax, out);
  case 1: return detail::intersectTriangleCorners<1>(ray, p0, p1, p2, tMax, out);
  default: return detail::intersectTriangleCorners<2>(ray, p0, p1, p2, tMax, out);
  }
}

/// The same for a mesh's float corners (the same result as their Vec3
/// values), with the ray's axis fixed at compile time: callers dispatch on
/// ray.kz once per ray, not once per triangle.
template <int Kz>
inline bool intersectFloatTriangle(const WatertightRay &ray, const Vec3f &p0, const Vec3f &p1,
                                   const Vec3f &p2, double tMax, TriangleHitParams &out) {
  return detail::intersectTriangleCorners<Kz>(ray, p0, p1, p2, tMax, out);
}

} // namespace lray
