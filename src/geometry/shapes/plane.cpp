// Pipeline: geometry. The plane y = 0 in object space.
#include "geometry/shapes/plane.h"

#include <limits>

namespace lray {

Bounds3 Plane::worldBounds(const Mat4 &) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {{-inf, -inf, -inf}, {inf, inf, inf}};
}

bool Plane::intersect(const Ray &ray, ObjectHit &hit) const {
  if (ray.d.y == 0) return false; // parallel: never meets it (or lies in it)
  double t = -ray.o.y / ray.d.y;
  if (!inOpenRange(ray, t)) return false;
  hit.t = t;
  hit.part = 0;
  return true;
}

int Plane::spans(const Ray &ray, Span *out) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (ray.d.y == 0) {
    if (!(ray.o.y < 0)) return 0;
    out[0] = {-inf, inf, -1, -1}; // a line below the plane, parallel to it
    return 1;
  }
  double t = -ray.o.y / ray.d.y;
  out[0] = ray.d.y > 0 ? Span{-inf, t, -1, 0} : Span{t, inf, 0, -1};
  return 1;
}

ObjectSurface Plane::surface(const Ray &ray, const ObjectHit &hit) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  p.y = 0; // snap onto the plane
  s.p = p;
  s.n = {0, 1, 0};
  s.u = p.x;
  s.v = p.z;
  return s;
}

std::optional<Wide> Plane::refine(const WideRay &ray, Wide s, Wide, int) const {
  return planeRefine(ray.o.y, ray.d.y, 0, s);
}

} // namespace lray
