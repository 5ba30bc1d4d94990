// Pipeline: geometry. Torus: the points at distance `minor` from the circle
// of radius `major` around +y in the xz-plane of its object space. One part
// (0). uv: u = turn fraction about +y from +x towards +z (as the cylinder's
// side), v = turn fraction about the tube, from the outer equator (v = 0)
// towards +y. The ray test is the quartic's, solved robustly (torus.cpp).
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

namespace lray {

struct Torus {
  static constexpr const char *kName = "Torus";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  double major = 1;    ///< radius of the centre circle (object units)
  double minor = 0.25; ///< radius of the tube

  /// Exact world box: the centre circle's box widened by the tube's ellipsoid.
  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const {
    return closestApproachShift(ray, {}, kFarOrigin * (major + minor));
  }
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  /// The hit's surface; its (u, v) only when `uv` (Entity::readsUv).
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit, bool uv = true) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

} // namespace lray
