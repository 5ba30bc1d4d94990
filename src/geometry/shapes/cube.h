// Pipeline: geometry. Cube (lua/README.md, "Entities"): side 1, centred at the origin of its
// object space. Parts: 2 * axis + (1 if the face is on the + side), axis
// 0 = x; the faces' uv orientation is in cube.cpp.
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

namespace lray {

struct Cube {
  static constexpr const char *kName = "Cube";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const { return closestApproachShift(ray, {}, kFarOrigin); }
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

} // namespace lray
