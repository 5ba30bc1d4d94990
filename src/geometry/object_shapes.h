// Pipeline: geometry (internal). The analytic shapes in their own object
// space (SPEC 5 default geometry), before any entity transform: the ray
// tests and the surface quantities (point, normal, uv) at a hit. shape.cpp
// transforms rays into this space and results back to world space.
#pragma once

#include "math/ray.h"
#include "math/vec3.h"

#include <cmath>

namespace lray {

/// Result of an object-space ray test: the ray parameter and which part of
/// the surface was hit (shape-specific; see each shape's `Part`).
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

/// Unit sphere at the origin. Part 0 only.
bool intersectSphere(const Ray &ray, ObjectHit &hit);
ObjectSurface sphereSurface(const Ray &ray, const ObjectHit &hit);

/// Radius-1 cylinder around +y from y = 0 to y = 1.
/// Parts: 0 side, 1 bottom cap (y = 0), 2 top cap (y = 1).
bool intersectCylinder(const Ray &ray, bool open, ObjectHit &hit);
ObjectSurface cylinderSurface(const Ray &ray, const ObjectHit &hit);

/// Cone with base radius 1 at y = 0 and apex at (0, 1, 0).
/// Parts: 0 side, 1 base cap (y = 0).
bool intersectCone(const Ray &ray, bool open, ObjectHit &hit);
ObjectSurface coneSurface(const Ray &ray, const ObjectHit &hit);

/// Axis-aligned cube of side 1 centred at the origin.
/// Parts: 2 * axis + (1 if the face is on the + side), axis 0 = x.
bool intersectCube(const Ray &ray, ObjectHit &hit);
ObjectSurface cubeSurface(const Ray &ray, const ObjectHit &hit);

// --- Shared numerics --------------------------------------------------------

constexpr double kShapePi = 3.14159265358979323846;

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
  if (a < 0) a += 2 * kShapePi;
  double u = a / (2 * kShapePi);
  return u < 1 ? u : 0;
}

inline bool inOpenRange(const Ray &ray, double t) { return t > ray.tMin && t < ray.tMax; }

} // namespace lray
