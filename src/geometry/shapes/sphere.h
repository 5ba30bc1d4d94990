// Pipeline: geometry. Sphere (lua/README.md, "Entities"): the unit sphere at the origin of its
// object space. One part (0). uv: u = (atan2(z, x) + pi) / (2 pi),
// v = (y + 1) / 2.
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

namespace lray {

struct Sphere {
  static constexpr const char *kName = "Sphere";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  /// Tight world box of the sphere placed by `worldFromObject` (unpadded).
  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const { return closestApproachShift(ray, {}, kFarOrigin); }
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  /// The hit's surface; its (u, v) only when `uv` (Entity::readsUv).
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit, bool uv = true) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

} // namespace lray
