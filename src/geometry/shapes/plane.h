// Pipeline: geometry. Plane: the infinite plane y = 0 of its object space,
// normal +y, one part (0), uv = the local (x, z) of the hit; its solid side
// is below (y <= 0). Unbounded: the backends keep it
// out of their trees (accel/unbounded_shapes.h).
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

namespace lray {

struct Plane {
  static constexpr const char *kName = "Plane";
  static constexpr bool kBounded = false;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  /// The plane in object space, for code that reasons about it whole
  /// (shading/shadow_shaft.cpp): its normal, out of the solid side, and a
  /// point on it.
  static constexpr Vec3 kObjectNormal{0, 1, 0};
  static constexpr Vec3 kObjectPoint{0, 0, 0};
  /// The plane placed by `worldFromObject`: the points p with
  /// dot(normal, p) = offset, normal of unit length and out of the solid
  /// side.
  struct WorldPlane {
    Vec3 normal;
    double offset;
  };
  static WorldPlane inWorld(const Transform &worldFromObject) {
    const Vec3 n = normalize(worldFromObject.applyNormal(kObjectNormal));
    return {n, dot(n, worldFromObject.applyPoint(kObjectPoint))};
  }

  /// The whole space: a plane has no finite box (unless axis-aligned, which
  /// is not worth a tree entry of its own).
  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  /// No re-origin: t = -o.y / d.y does not cancel for a distant origin.
  double originShift(const Ray &) const { return 0; }
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

} // namespace lray
