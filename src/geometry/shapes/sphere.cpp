// Pipeline: geometry. The unit sphere in object space (lua/README.md, "Entities").
#include "geometry/shapes/sphere.h"

namespace lray {

Bounds3 Sphere::worldBounds(const Mat4 &mat) const {
  // Exact box of an ellipsoid: half-extent along axis i is the norm of
  // row i of the linear part (the support function of the unit ball).
  const auto &m = mat.m;
  Vec3 c{m[0][3], m[1][3], m[2][3]};
  Vec3 e{std::sqrt(m[0][0] * m[0][0] + m[0][1] * m[0][1] + m[0][2] * m[0][2]),
         std::sqrt(m[1][0] * m[1][0] + m[1][1] * m[1][1] + m[1][2] * m[1][2]),
         std::sqrt(m[2][0] * m[2][0] + m[2][1] * m[2][1] + m[2][2] * m[2][2])};
  return {c - e, c + e};
}

int Sphere::spans(const Ray &ray, Span *out) const {
  double t0, t1;
  // A tangent line (t0 = t1) touches without entering.
  if (!sphere_detail::roots(ray, t0, t1) || !(t0 < t1)) return 0;
  out[0] = {t0, t1, 0, 0};
  return 1;
}

ObjectSurface Sphere::surface(const Ray &ray, const ObjectHit &hit, bool uv) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  double len = length(p);
  // Snap onto the sphere: removes the error of o + t d along the normal.
  if (len > 0) p = p / len;
  else p = {0, 1, 0};
  s.p = p;
  s.n = p;
  if (!uv) return s;
  s.u = sphereU(p.x, p.z);
  s.v = sphereV(p.y);
  return s;
}

std::optional<Wide> Sphere::refine(const WideRay &ray, Wide s, Wide shift, int) const {
  return newtonRefine(ray, s, shift, [](const WideVec &p, const WideVec &d) {
    return WideSlope{p.x * p.x + p.y * p.y + p.z * p.z - 1,
                     2 * (p.x * d.x + p.y * d.y + p.z * d.z)};
  });
}

} // namespace lray
