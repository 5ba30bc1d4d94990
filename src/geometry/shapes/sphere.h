// Pipeline: geometry. Sphere (lua/README.md, "Entities"): the unit sphere at the origin of its
// object space. One part (0). uv: u = (atan2(z, x) + pi) / (2 pi),
// v = (y + 1) / 2.
#pragma once

#include "math/bounds.h"
#include "geometry/shapes/object_space.h"
#include "math/transform.h"
#include "math/constants.h"

#include <cmath>

namespace lray {

struct Sphere {
  static constexpr const char *kName = "Sphere";
  static constexpr bool kBounded = true;
  static constexpr bool kSolid = true; ///< has an inside: CSG takes it (shape_list.h)

  /// Tight world box of the sphere placed by `worldFromObject` (unpadded).
  Bounds3 worldBounds(const Mat4 &worldFromObject) const;
  double originShift(const Ray &ray) const { return closestApproachShift(ray, {}, kFarOrigin); }
  /// True only where the line of `ray` (object space, before originShift)
  /// passes the sphere by a clear margin, so that intersect, after any
  /// origin shift, finds no hit: most of the lines a backend's box lets
  /// through are settled without the shift's division (sphere_detail).
  bool missesLine(const Ray &ray) const;
  /// Inline: most of a shadow ray's tests among many spheres are a few
  /// products and a miss.
  bool intersect(const Ray &ray, ObjectHit &hit) const;
  /// Where the whole line of `ray` is inside the solid (CSG); at most
  /// kMaxSpans, in order.
  int spans(const Ray &ray, Span *out) const;
  /// The hit's surface; its (u, v) only when `uv` (Entity::readsUv).
  ObjectSurface surface(const Ray &ray, const ObjectHit &hit, bool uv = true) const;
  std::optional<Wide> refine(const WideRay &ray, Wide s, Wide shift, int part) const;
};

/// The uv of a point (x, y, z) of the unit sphere (the header's mapping):
/// Sphere::surface's, and the four-lane fill's (geometry/shape.cpp).
inline double sphereU(double x, double z) { return (std::atan2(z, x) + kPi) / (2 * kPi); }
inline double sphereV(double y) { return (y + 1) / 2; }

namespace sphere_detail {

/// The roots t0 <= t1 of the ray's line with the unit sphere; false when the
/// line misses it. `Outward`: false also when the ray starts outside
/// (c = |o|^2 - 1 > 0), moves away from the centre (h = o.d > 0) and has
/// tMin >= 0: then no root lies past tMin, and the roots agree bit for bit
/// (quadraticRoots' q = -(h + sqrt(disc)) is negative, so q / a and c / q
/// are not positive). That skips the square root and divisions for a
/// shadow ray leaving a sphere's lit side.
template <bool Outward = false> inline bool roots(const Ray &ray, double &t0, double &t1) {
  const Vec3 &o = ray.o, &d = ray.d;
  double a = dot(d, d);
  if (!(a > 0)) return false;
  double h = dot(o, d);
  const double oo = dot(o, o);
  // Most tested lines miss: a |o|^2 - h^2 (a times the squared distance of
  // the line from the centre) settles them without the division below. Its
  // rounding, at most about 20 u |o|^2 a (u = 2^-53), and the test below's,
  // are far inside the margin, so this only drops lines that test drops.
  if (oo * a - h * h > a * (1 + 1e-12 * (1 + oo))) return false;
  if (Outward && ray.tMin >= 0 && h > 0 && oo - 1 > 0) return false;
  // The reduced discriminant h^2 - a c equals a (1 - |v|^2), v = the ray's
  // closest point to the centre; this form does not cancel for distant or
  // grazing rays (pbrt-v4's sphere test).
  Vec3 v = o - d * (h / a);
  double disc = a * (1 - dot(v, v));
  if (disc < 0) return false;
  double c = oo - 1;
  quadraticRoots(a, h, c, disc, t0, t1);
  return true;
}

/// Lines no farther than this from the centre go to the full test: with
/// an origin shifted to the closest approach (|o| up to kMaxPrefilteredOrigin)
/// the full test's rounding is far inside it.
constexpr double kClearMargin = 1e-3;
constexpr double kMaxPrefilteredOrigin = 1e10;

} // namespace sphere_detail

inline bool Sphere::missesLine(const Ray &ray) const {
  // a |o|^2 - h^2 is a times the line's squared distance from the centre
  // (a = |d|^2, h = o.d): roots() tests the same expression, after the
  // shift when the origin is far, where it cannot cancel. Unshifted its
  // rounding is at most about 16 u |o|^2 a (u = 2^-53), which the
  // 1e-12 |o|^2 a term covers, so a true answer means the line passes at
  // more than sqrt(1 + kClearMargin) radii. The shifted origin is then
  // within a few u |o| of the closest point, so roots() sees the line as
  // far outside its own threshold as well (for |o| up to
  // kMaxPrefilteredOrigin; and unshifted, this threshold is above
  // roots()'s). NaN and a = 0: false.
  const Vec3 &o = ray.o, &d = ray.d;
  const double a = dot(d, d);
  const double h = dot(o, d);
  const double oo = dot(o, o);
  using namespace sphere_detail;
  return oo < kMaxPrefilteredOrigin * kMaxPrefilteredOrigin &&
         oo * a - h * h > a * (1 + kClearMargin) + 1e-12 * oo * a;
}

inline bool Sphere::intersect(const Ray &ray, ObjectHit &hit) const {
  double t0, t1;
  if (!sphere_detail::roots<true>(ray, t0, t1)) return false;
  if (inOpenRange(ray, t0)) {
    hit.t = t0;
  } else if (inOpenRange(ray, t1)) {
    hit.t = t1;
  } else {
    return false;
  }
  hit.part = 0;
  return true;
}

} // namespace lray
