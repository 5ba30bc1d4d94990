// Pipeline: geometry. Cube (lua/README.md, "Entities"): side 1, centred at the origin of its
// object space. Parts: 2 * axis + (1 if the face is on the + side), axis
// 0 = x; the faces' uv orientation is in cube.cpp.
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

#include <limits>

namespace lray {

struct Cube {
  static constexpr const char *kName = "Cube";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const { return closestApproachShift(ray, {}, kFarOrigin); }
  /// Inline, as Sphere's: shadow rays make many tests.
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

namespace cube_detail {

/// The line of `ray` inside the three slabs: [tNear, tFar] entering through
/// face nearPart and leaving through farPart; false when it misses them.
inline bool slabInterval(const Ray &ray, double &tNear, double &tFar, int &nearPart, int &farPart) {
  tNear = -std::numeric_limits<double>::infinity();
  tFar = std::numeric_limits<double>::infinity();
  nearPart = farPart = -1;
  for (int axis = 0; axis < 3; ++axis) {
    double o = ray.o[axis], d = ray.d[axis];
    if (d == 0) {
      // Parallel to this slab: inside it (boundary included) or a miss.
      if (o < -0.5 || o > 0.5) return false;
      continue;
    }
    clipToSlab((-0.5 - o) / d, (0.5 - o) / d, 2 * axis, 2 * axis + 1, tNear, tFar, nearPart,
               farPart);
  }
  return !(tNear > tFar) && nearPart >= 0;
}

} // namespace cube_detail

inline bool Cube::intersect(const Ray &ray, ObjectHit &hit) const {
  double tNear, tFar;
  int nearPart, farPart;
  if (!cube_detail::slabInterval(ray, tNear, tFar, nearPart, farPart)) return false;
  if (inOpenRange(ray, tNear)) {
    hit.t = tNear;
    hit.part = nearPart;
    return true;
  }
  if (inOpenRange(ray, tFar)) {
    hit.t = tFar;
    hit.part = farPart;
    return true;
  }
  return false;
}

} // namespace lray
