// Pipeline: acceleration (kd-tree backend). Sutherland-Hodgman clipping of a
// triangle against the six planes of a box.
#include "accel/kdtree/triangle_clip.h"

#include <utility>

namespace lray {

namespace {

// A triangle clipped by six planes has at most 3 + 6 corners.
constexpr int kMaxCorners = 9;

// Corners as plain arrays, so a plane's axis indexes them directly.
struct Polygon {
  double p[kMaxCorners + 1][3];
  int n = 0;
};

// Keeps the part with sign * (p[axis] - plane) <= 0.
void clipPolygon(const Polygon &in, Polygon &out, int axis, double plane, double sign) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const double *cur = in.p[i];
    const double *next = in.p[i + 1 < in.n ? i + 1 : 0];
    double dc = sign * (cur[axis] - plane), dn = sign * (next[axis] - plane);
    if (dc <= 0) {
      double *q = out.p[out.n++];
      q[0] = cur[0];
      q[1] = cur[1];
      q[2] = cur[2];
    }
    if ((dc < 0 && dn > 0) || (dc > 0 && dn < 0)) {
      double f = dc / (dc - dn);
      double *q = out.p[out.n++];
      for (int k = 0; k < 3; ++k) q[k] = cur[k] + (next[k] - cur[k]) * f;
      q[axis] = plane; // exactly on the plane, whatever the rounding above
    }
  }
}

} // namespace

Bounds3 clipTriangleToBox(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Bounds3 &box) {
  Bounds3 whole(a, b);
  whole.extend(c);
  if (whole.lo.x >= box.lo.x && whole.lo.y >= box.lo.y && whole.lo.z >= box.lo.z &&
      whole.hi.x <= box.hi.x && whole.hi.y <= box.hi.y && whole.hi.z <= box.hi.z)
    return whole;

  // Two buffers used in turn: each plane clips one into the other.
  Polygon buffers[2];
  Polygon *poly = &buffers[0], *tmp = &buffers[1];
  const Vec3 *corners[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    poly->p[i][0] = corners[i]->x;
    poly->p[i][1] = corners[i]->y;
    poly->p[i][2] = corners[i]->z;
  }
  poly->n = 3;
  const double boxLo[3] = {box.lo.x, box.lo.y, box.lo.z};
  const double boxHi[3] = {box.hi.x, box.hi.y, box.hi.z};
  const double wholeLo[3] = {whole.lo.x, whole.lo.y, whole.lo.z};
  const double wholeHi[3] = {whole.hi.x, whole.hi.y, whole.hi.z};
  // Only the planes the triangle crosses (clipping never grows the polygon).
  for (int axis = 0; axis < 3 && poly->n > 0; ++axis) {
    if (wholeLo[axis] < boxLo[axis]) {
      clipPolygon(*poly, *tmp, axis, boxLo[axis], -1);
      std::swap(poly, tmp);
    }
    if (wholeHi[axis] > boxHi[axis] && poly->n > 0) {
      clipPolygon(*poly, *tmp, axis, boxHi[axis], 1);
      std::swap(poly, tmp);
    }
  }
  Bounds3 result;
  for (int i = 0; i < poly->n; ++i)
    result.extend(Vec3(poly->p[i][0], poly->p[i][1], poly->p[i][2]));
  if (result.empty()) return result;
  result.lo = max(result.lo, box.lo);
  result.hi = min(result.hi, box.hi);
  return result;
}

} // namespace lray
