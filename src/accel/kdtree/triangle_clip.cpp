// Pipeline: acceleration (kd-tree backend). Sutherland-Hodgman clipping of a
// triangle against the six planes of a box.
#include "accel/kdtree/triangle_clip.h"

namespace lray {

namespace {

// A triangle clipped by six planes has at most 3 + 6 corners.
constexpr int kMaxCorners = 9;

struct Polygon {
  Vec3 p[kMaxCorners + 1];
  int n = 0;
};

// Keeps the part with sign * (p[axis] - plane) <= 0.
void clipPolygon(const Polygon &in, Polygon &out, int axis, double plane, double sign) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const Vec3 &cur = in.p[i];
    const Vec3 &next = in.p[(i + 1) % in.n];
    double dc = sign * (cur[axis] - plane), dn = sign * (next[axis] - plane);
    if (dc <= 0) out.p[out.n++] = cur;
    if ((dc < 0 && dn > 0) || (dc > 0 && dn < 0)) {
      Vec3 q = cur + (next - cur) * (dc / (dc - dn));
      q[axis] = plane; // exactly on the plane, whatever the rounding above
      out.p[out.n++] = q;
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

  Polygon poly, tmp;
  poly.p[0] = a;
  poly.p[1] = b;
  poly.p[2] = c;
  poly.n = 3;
  // Only the planes the triangle crosses (clipping never grows the polygon).
  for (int axis = 0; axis < 3 && poly.n > 0; ++axis) {
    if (whole.lo[axis] < box.lo[axis]) {
      clipPolygon(poly, tmp, axis, box.lo[axis], -1);
      poly = tmp;
    }
    if (whole.hi[axis] > box.hi[axis] && poly.n > 0) {
      clipPolygon(poly, tmp, axis, box.hi[axis], 1);
      poly = tmp;
    }
  }
  Bounds3 result;
  for (int i = 0; i < poly.n; ++i) result.extend(poly.p[i]);
  if (result.empty()) return result;
  result.lo = max(result.lo, box.lo);
  result.hi = min(result.hi, box.hi);
  return result;
}

} // namespace lray
