// Pipeline: geometry. The unit sphere in object space (SPEC 5 Sphere).
#include "geometry/object_shapes.h"

namespace lray {

bool intersectSphere(const Ray &ray, ObjectHit &hit) {
  const Vec3 &o = ray.o, &d = ray.d;
  double a = dot(d, d);
  if (!(a > 0)) return false;
  double h = dot(o, d);
  // The reduced discriminant h^2 - a c equals a (1 - |v|^2), v = the ray's
  // closest point to the centre; this form does not cancel for distant or
  // grazing rays (pbrt-v4's sphere test).
  Vec3 v = o - d * (h / a);
  double disc = a * (1 - dot(v, v));
  if (disc < 0) return false;
  double c = dot(o, o) - 1;
  double t0, t1;
  quadraticRoots(a, h, c, disc, t0, t1);
  if (inOpenRange(ray, t0)) {
    hit.t = t0;
  } else if (inOpenRange(ray, t1)) {
    hit.t = t1;
  } else {
    return false;
  }
  hit.part = 0;
  return true;
}

ObjectSurface sphereSurface(const Ray &ray, const ObjectHit &hit) {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  double len = length(p);
  // Snap onto the sphere: removes the error of o + t d along the normal.
  if (len > 0) p = p / len;
  else p = {0, 1, 0};
  s.p = p;
  s.n = p;
  s.u = (std::atan2(p.z, p.x) + kShapePi) / (2 * kShapePi);
  s.v = (p.y + 1) / 2;
  return s;
}

} // namespace lray
