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
#include <utility>

namespace lray {

/// A ray prepared for the watertight test: the axis along which it moves
/// most becomes z (kz); kx, ky are the other two in an order that keeps the
/// triangle's winding; (sx, sy, sz) shear the ray direction onto (0, 0, 1).
/// The permutation and shear are stored as three rows, so a vertex v maps to
/// (dot(rowX, v), dot(rowY, v), dot(rowZ, v)) without branches: each row has
/// one or two non-zero entries (1 and -s), so the dot product rounds exactly
/// as v[kx] - sx * v[kz] does.
struct WatertightRay {
  Vec3 o;
  Vec3 rowX, rowY, rowZ;
  double tMin = 0;

  explicit WatertightRay(const Ray &ray) : o(ray.o), tMin(ray.tMin) {
    Vec3 ad = abs(ray.d);
    int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = (kz + 1) % 3;
    int ky = (kx + 1) % 3;
    if (ray.d[kz] < 0) std::swap(kx, ky);
    rowX[kx] = 1;
    rowX[kz] = -(ray.d[kx] / ray.d[kz]);
    rowY[ky] = 1;
    rowY[kz] = -(ray.d[ky] / ray.d[kz]);
    rowZ[kz] = 1.0 / ray.d[kz];
  }
};

/// Ray parameter and barycentrics of corners 1 and 2 (corner 0 has 1 - b1 - b2).
struct TriangleHitParams {
  double t = 0, b1 = 0, b2 = 0;
};

/// Watertight intersection of the ray with triangle (p0, p1, p2), both in the
/// same space, for t in (ray.tMin, tMax). Either facing is hit; a triangle
/// seen exactly edge-on is missed.
inline bool intersectTriangle(const WatertightRay &ray, const Vec3 &p0, const Vec3 &p1,
                              const Vec3 &p2, double tMax, TriangleHitParams &out) {
  // Vertices relative to the origin, then sheared so the ray runs along +z.
  const Vec3 a = p0 - ray.o, b = p1 - ray.o, c = p2 - ray.o;
  const double ax = dot(ray.rowX, a), ay = dot(ray.rowY, a);
  const double bx = dot(ray.rowX, b), by = dot(ray.rowY, b);
  const double cx = dot(ray.rowX, c), cy = dot(ray.rowY, c);

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
  const double det = e0 + e1 + e2;
  if (det == 0) return false;

  // Scaled hit distance, compared before dividing.
  const double az = dot(ray.rowZ, a), bz = dot(ray.rowZ, b), cz = dot(ray.rowZ, c);
  const double tScaled = e0 * az + e1 * bz + e2 * cz;
  const double invDet = 1.0 / det;
  const double t = tScaled * invDet;
  if (!(t > ray.tMin && t < tMax)) return false;
  out.t = t;
  out.b1 = e1 * invDet;
  out.b2 = e2 * invDet;
  return true;
}

} // namespace lray
