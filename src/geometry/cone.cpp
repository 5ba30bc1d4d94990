// Pipeline: geometry. The cone in object space (SPEC 5 Cone): base radius 1
// at y = 0, apex at (0, 1, 0), base capped unless `open`.
#include "geometry/object_shapes.h"

#include <algorithm>

namespace lray {

bool intersectCone(const Ray &ray, bool open, ObjectHit &hit) {
  const Vec3 &o = ray.o, &d = ray.d;
  bool found = false;
  double best = ray.tMax;
  // Side: x^2 + z^2 = (1 - y)^2 with 0 <= y <= 1 (the other nappe, y > 1,
  // is rejected). With k = 1 - y: a t^2 + 2 h t + c = 0.
  double k = 1 - o.y;
  double a = d.x * d.x + d.z * d.z - d.y * d.y;
  double h = o.x * d.x + o.z * d.z + k * d.y;
  double c = o.x * o.x + o.z * o.z - k * k;
  double disc = differenceOfProducts(h, h, a, c);
  // A ray through the apex has a double root (disc = 0 exactly); keep it
  // when rounding made the discriminant a few ulps negative.
  if (disc < 0 && disc > -8 * 0x1p-53 * (h * h + std::fabs(a * c))) disc = 0;
  if (disc >= 0) {
    double roots[2] = {std::nan(""), std::nan("")};
    if (a == 0) {
      // Ray parallel to a generator line: a single root (none if h = 0).
      if (h != 0) roots[0] = -c / (2 * h);
    } else {
      quadraticRoots(a, h, c, disc, roots[0], roots[1]);
    }
    for (double t : roots) {
      if (!inOpenRange(ray, t) || t >= best) continue;
      double y = o.y + t * d.y;
      if (y < 0 || y > 1) continue;
      best = t;
      hit.t = t;
      hit.part = 0;
      found = true;
      break;
    }
  }
  if (!open && d.y != 0) {
    double t = -o.y / d.y;
    if (inOpenRange(ray, t) && t < best) {
      double x = o.x + t * d.x, z = o.z + t * d.z;
      if (x * x + z * z <= 1) {
        hit.t = t;
        hit.part = 1;
        found = true;
      }
    }
  }
  return found;
}

ObjectSurface coneSurface(const Ray &ray, const ObjectHit &hit) {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  if (hit.part == 0) {
    p.y = std::clamp(p.y, 0.0, 1.0);
    double r = std::sqrt(p.x * p.x + p.z * p.z);
    double k = 1 - p.y;
    // Snap radially onto the cone; at the apex the normal is taken as +y.
    if (r > 0) {
      p.x *= k / r;
      p.z *= k / r;
    }
    s.n = k > 0 && r > 0 ? Vec3(p.x, k, p.z) : Vec3(0, 1, 0);
    s.u = turnFraction(p.x, p.z);
    s.v = p.y;
  } else {
    p.y = 0;
    s.n = {0, -1, 0};
    s.u = std::clamp((p.x + 1) / 2, 0.0, 1.0);
    s.v = std::clamp((p.z + 1) / 2, 0.0, 1.0);
  }
  s.p = p;
  return s;
}

} // namespace lray
