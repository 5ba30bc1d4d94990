// Pipeline: geometry (internal). What every analytic shape's own file
// (shapes/*.h) works with: an object-space ray test's result, the surface
// quantities at a hit, the shared numerics of the ray tests, and the long-
// double helpers of the grazing-hit refinement. World space is shape.cpp's.
#pragma once

#include "math/error_bound.h"
#include "geometry/shapes/span.h"
#include "math/constants.h"
#include "math/ray.h"
#include "math/vec3.h"

#include <cmath>
#include <optional>
#include <utility>

namespace lray {

/// Result of an object-space ray test: the ray parameter and which part of
/// the surface was hit (shape-specific; see each shape's parts).
struct ObjectHit {
  double t = 0;
  int part = 0;
};

/// Surface quantities at an object-space hit.
struct ObjectSurface {
  Vec3 p; ///< hit point, snapped onto the surface
  Vec3 n; ///< outward normal, object space, not normalised
  double u = 0, v = 0;
};

// --- Shared numerics --------------------------------------------------------

/// a*b - c*d with one rounding's worth of error (Kahan's fma trick), used
/// for discriminants where b^2 and a*c nearly cancel.
inline double differenceOfProducts(double a, double b, double c, double d) {
  double cd = c * d;
  double err = std::fma(-c, d, cd);
  double dop = std::fma(a, b, -cd);
  return dop + err;
}

/// Roots t0 <= t1 of a t^2 + 2 h t + c = 0 given the reduced discriminant
/// disc = h^2 - a c >= 0, in the cancellation-free form
/// q = -(h + sign(h) sqrt(disc)), roots q / a and c / q. A zero `a` gives one
/// infinite root, which range checks reject.
inline void quadraticRoots(double a, double h, double c, double disc, double &t0, double &t1) {
  double q = -(h + std::copysign(std::sqrt(disc), h));
  if (q == 0) { // h = 0 and disc = 0: the double root is 0
    t0 = t1 = 0;
    return;
  }
  t0 = q / a;
  t1 = c / q;
  if (t0 > t1) std::swap(t0, t1);
}

/// Angle of (x, z) about +y, measured from +x towards +z, as a fraction of a
/// turn in [0, 1).
inline double turnFraction(double x, double z) {
  double a = std::atan2(z, x);
  if (a < 0) a += 2 * kPi;
  double u = a / (2 * kPi);
  return u < 1 ? u : 0;
}

inline bool inOpenRange(const Ray &ray, double t) { return t > ray.tMin && t < ray.tMax; }

/// Narrows a line's interval [lo, hi] (entered through part loPart, left
/// through hiPart) to its crossing [t0, t1] of a slab between two planes,
/// parts p0 and p1 (t0 and t1 in either order).
inline void clipToSlab(double t0, double t1, int p0, int p1, double &lo, double &hi, int &loPart,
                       int &hiPart) {
  if (t0 > t1) {
    std::swap(t0, t1);
    std::swap(p0, p1);
  }
  if (t0 > lo) {
    lo = t0;
    loPart = p0;
  }
  if (t1 < hi) {
    hi = t1;
    hiPart = p1;
  }
}

/// Beyond this distance (object units) from a unit-sized shape's centre a
/// ray origin makes the quadric coefficients cancel (the cone's
/// o.o - (1 - o_y)^2 loses everything at |o| ~ 1e6).
constexpr double kFarOrigin = 4;

/// How far along `ray` to re-origin it before a shape's test: to its closest
/// approach to `centre` when the origin is more than `farOrigin` away on
/// some axis, else 0. The test's t is then relative to that point and
/// shape.cpp adds the shift back.
inline double closestApproachShift(const Ray &ray, const Vec3 &centre, double farOrigin) {
  Vec3 oc = centre - ray.o;
  if (maxAbsComponent(oc) <= farOrigin) return 0;
  double dd = dot(ray.d, ray.d);
  return dd > 0 ? dot(oc, ray.d) / dd : 0;
}

// --- Grazing-hit refinement in long double -----------------------------------

using Wide = long double;

struct WideVec {
  Wide x, y, z;
};

/// An object-space ray in long double (shape.cpp makes it exact to long
/// double by iterative refinement against worldFromObject).
struct WideRay {
  WideVec o, d;
  WideVec at(Wide s) const { return {o.x + s * d.x, o.y + s * d.y, o.z + s * d.z}; }
};

/// f and df/ds of a shape's implicit function along a ray.
struct WideSlope {
  Wide f, df;
};

/// Two Newton steps from s on the implicit surface `slope(p, d)` (p =
/// ray.at(s), d = ray.d).
/// Newton never leaves the root the double test chose: a step beyond a
/// relative 1e-9 means a degenerate (tangent) configuration, and nullopt
/// says to keep the double t. `shift` is shape.cpp's re-origin distance.
template <class Slope>
std::optional<Wide> newtonRefine(const WideRay &ray, Wide s, Wide shift, Slope slope) {
  const Wide start = s;
  for (int i = 0; i < 2; ++i) {
    WideSlope fs = slope(ray.at(s), ray.d);
    if (!(fs.df != 0)) break;
    s -= fs.f / fs.df;
  }
  if (!(std::fabs(s - start) <= 1e-9L * (std::fabs(start) + std::fabs(shift))))
    return std::nullopt;
  return s;
}

/// The exact parameter where the ray's coordinate (origin oc, direction dc)
/// reaches `at`: flat parts (caps, cube faces) need no iteration.
inline Wide planeRefine(Wide oc, Wide dc, Wide at, Wide s) { return dc != 0 ? (at - oc) / dc : s; }

} // namespace lray
