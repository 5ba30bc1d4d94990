// Pipeline: acceleration (kd-tree backend). Bounds of the part of a triangle
// inside a box, for the kd-tree's "perfect splits" (Wald & Havran 2006):
// split candidates come from the clipped triangle, not its whole bounds.
#pragma once

#include "math/bounds.h"
#include "math/vec3.h"

namespace lray {

/// Bounds of triangle (a, b, c) clipped to `box` (same space, any units);
/// empty when the triangle misses the box. The result lies inside `box`.
Bounds3 clipTriangleToBox(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Bounds3 &box);

} // namespace lray
