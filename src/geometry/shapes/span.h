// Pipeline: geometry. A stretch of a ray inside a solid, the unit of CSG
// (geometry/csg.h): each solid shape lists where its ray, taken over the
// whole line (tMin and tMax ignored), is inside it.
#pragma once

namespace lray {

/// The ray is inside the solid for t in [t0, t1], entering through part
/// `part0` and leaving through `part1` (the shape's parts, as in ObjectHit).
/// An end at -inf or +inf (a half-space) has part -1.
struct Span {
  double t0, t1;
  int part0, part1;
};

/// The most spans one shape gives along a line (the torus: 2).
constexpr int kMaxSpans = 2;

} // namespace lray
