// Pipeline: geometry. Cone (lua/README.md, "Entities"): base radius 1 at y = 0, apex at
// (0, 1, 0) in object space, base capped unless `open`. Parts: 0 side
// (u = turn fraction from +x towards +z, v = y), 1 base cap (u = (x + 1) / 2,
// v = (z + 1) / 2).
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"

namespace lray {

struct Cone {
  static constexpr const char *kName = "Cone";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< while closed: see hollowedBy()

  bool open = false; ///< no base cap (ext)
  /// The attribute that leaves this one without an inside while it is set
  /// (open: no base cap), else null (shape_list.h, hollowedBy).
  const char *hollowedBy() const { return open ? "open" : nullptr; }

  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const {
    return closestApproachShift(ray, {0, 0.5, 0}, kFarOrigin);
  }
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order. Caps included even when `open`: CSG refuses open
  /// ones.
  int spans(const Ray &ray, Span *out) const;
  /// The hit's surface; its (u, v) only when `uv` (Entity::readsUv).
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit, bool uv = true) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

} // namespace lray
