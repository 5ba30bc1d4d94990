// Pipeline: geometry. The capped cylinder in object space (lua/README.md, "Entities",
// Cylinder): radius 1 around +y from y = 0 to y = 1; `open` drops the caps.
#include "geometry/shapes/cylinder.h"

#include "geometry/shapes/disc_bounds.h"

#include <algorithm>
#include <limits>

namespace lray {

namespace {

// Disc of radius 1 in the plane y = planeY.
bool intersectCap(const Ray &ray, double planeY, double &t) {
  if (ray.d.y == 0) return false;
  double tc = (planeY - ray.o.y) / ray.d.y;
  if (!inOpenRange(ray, tc)) return false;
  double x = ray.o.x + tc * ray.d.x, z = ray.o.z + tc * ray.d.z;
  if (x * x + z * z > 1) return false;
  t = tc;
  return true;
}

} // namespace

Bounds3 Cylinder::worldBounds(const Mat4 &mat) const {
  // The convex hull of the two end discs.
  Bounds3 b = discBounds(mat, 0);
  b.extend(discBounds(mat, 1));
  return b;
}

bool Cylinder::intersect(const Ray &ray, ObjectHit &hit) const {
  const Vec3 &o = ray.o, &d = ray.d;
  bool found = false;
  double best = ray.tMax;
  // Side: x^2 + z^2 = 1 with 0 <= y <= 1. A ray along the axis (a = 0)
  // never meets the side; the caps catch it.
  double a = d.x * d.x + d.z * d.z;
  if (a > 0) {
    double h = o.x * d.x + o.z * d.z;
    double vx = o.x - d.x * (h / a), vz = o.z - d.z * (h / a);
    double disc = a * (1 - (vx * vx + vz * vz));
    if (disc >= 0) {
      double c = o.x * o.x + o.z * o.z - 1;
      double roots[2];
      quadraticRoots(a, h, c, disc, roots[0], roots[1]);
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
  }
  if (!open) {
    for (int cap = 1; cap <= 2; ++cap) {
      double t;
      if (intersectCap(ray, cap == 1 ? 0.0 : 1.0, t) && t < best) {
        best = t;
        hit.t = t;
        hit.part = cap;
        found = true;
      }
    }
  }
  return found;
}

int Cylinder::spans(const Ray &ray, Span *out) const {
  const Vec3 &o = ray.o, &d = ray.d;
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Inside the infinite cylinder x^2 + z^2 <= 1 ...
  double lo = -inf, hi = inf;
  int loPart = -1, hiPart = -1;
  double a = d.x * d.x + d.z * d.z;
  if (a > 0) {
    double h = o.x * d.x + o.z * d.z;
    double vx = o.x - d.x * (h / a), vz = o.z - d.z * (h / a);
    double disc = a * (1 - (vx * vx + vz * vz));
    if (!(disc > 0)) return 0;
    double c = o.x * o.x + o.z * o.z - 1;
    quadraticRoots(a, h, c, disc, lo, hi);
    loPart = hiPart = 0;
  } else if (!(o.x * o.x + o.z * o.z < 1)) {
    return 0;
  }
  // ... and in the slab 0 <= y <= 1 between the caps (intersectCap's t).
  if (d.y != 0) {
    clipToSlab((0.0 - o.y) / d.y, (1.0 - o.y) / d.y, 1, 2, lo, hi, loPart, hiPart);
  } else if (!(o.y > 0 && o.y < 1)) {
    return 0;
  }
  if (!(lo < hi)) return 0;
  out[0] = {lo, hi, loPart, hiPart};
  return 1;
}

ObjectSurface Cylinder::surface(const Ray &ray, const ObjectHit &hit, bool uv) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  if (hit.part == 0) {
    double r = std::sqrt(p.x * p.x + p.z * p.z);
    if (r > 0) {
      p.x /= r;
      p.z /= r;
    }
    p.y = std::clamp(p.y, 0.0, 1.0);
    s.n = {p.x, 0, p.z};
    if (uv) s.u = turnFraction(p.x, p.z);
    s.v = p.y;
  } else {
    p.y = hit.part == 1 ? 0.0 : 1.0;
    s.n = {0, hit.part == 1 ? -1.0 : 1.0, 0};
    s.u = std::clamp((p.x + 1) / 2, 0.0, 1.0);
    s.v = std::clamp((p.z + 1) / 2, 0.0, 1.0);
  }
  s.p = p;
  return s;
}

std::optional<Wide> Cylinder::refine(const WideRay &ray, Wide s, Wide shift, int part) const {
  if (part != 0) return planeRefine(ray.o.y, ray.d.y, part == 1 ? 0 : 1, s);
  return newtonRefine(ray, s, shift, [](const WideVec &p, const WideVec &d) {
    return WideSlope{p.x * p.x + p.z * p.z - 1, 2 * (p.x * d.x + p.z * d.z)};
  });
}

} // namespace lray
