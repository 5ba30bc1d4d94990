// Pipeline: geometry. The unit cube in object space (lua/README.md, "Entities"): side 1,
// centred at the origin, intersected as three slabs (Kay and Kajiya 1986).
//
// Face uv orientation: each face is seen from outside, upright, with u to
// the right and v up in the left-handed frame of lua/README.md, "The scene file" (+y up); the top
// and bottom faces have +z as "up". So, with (x, y, z) in [-0.5, 0.5]:
//   -z: u = x + 0.5, v = y + 0.5     +z: u = 0.5 - x, v = y + 0.5
//   +x: u = z + 0.5, v = y + 0.5     -x: u = 0.5 - z, v = y + 0.5
//   +y: u = x + 0.5, v = z + 0.5     -y: u = 0.5 - x, v = z + 0.5
#include "geometry/shapes/cube.h"

#include "math/transform.h"

#include <algorithm>
#include <limits>

namespace lray {

Bounds3 Cube::worldBounds(const Mat4 &mat) const {
  Bounds3 b;
  for (int i = 0; i < 8; ++i)
    b.extend(affinePoint(mat, {i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5}));
  return b;
}

int Cube::spans(const Ray &ray, Span *out) const {
  double tNear, tFar;
  int nearPart, farPart;
  // A line along an edge or face (tNear = tFar) does not enter.
  if (!cube_detail::slabInterval(ray, tNear, tFar, nearPart, farPart) || !(tNear < tFar)) return 0;
  out[0] = {tNear, tFar, nearPart, farPart};
  return 1;
}

ObjectSurface Cube::surface(const Ray &ray, const ObjectHit &hit) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  int axis = hit.part / 2;
  double side = (hit.part & 1) ? 0.5 : -0.5;
  for (int i = 0; i < 3; ++i) p[i] = std::clamp(p[i], -0.5, 0.5);
  p[axis] = side;
  s.p = p;
  s.n = {0, 0, 0};
  s.n[axis] = side > 0 ? 1 : -1;
  switch (hit.part) {
  case 0: s.u = 0.5 - p.z; s.v = p.y + 0.5; break; // -x
  case 1: s.u = p.z + 0.5; s.v = p.y + 0.5; break; // +x
  case 2: s.u = 0.5 - p.x; s.v = p.z + 0.5; break; // -y
  case 3: s.u = p.x + 0.5; s.v = p.z + 0.5; break; // +y
  case 4: s.u = p.x + 0.5; s.v = p.y + 0.5; break; // -z
  default: s.u = 0.5 - p.x; s.v = p.y + 0.5; break; // +z
  }
  return s;
}

std::optional<Wide> Cube::refine(const WideRay &ray, Wide s, Wide, int part) const {
  const Wide oc[3] = {ray.o.x, ray.o.y, ray.o.z}, dc[3] = {ray.d.x, ray.d.y, ray.d.z};
  int axis = part / 2;
  return planeRefine(oc[axis], dc[axis], (part & 1) ? Wide(0.5) : Wide(-0.5), s);
}

} // namespace lray
