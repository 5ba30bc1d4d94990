// Pipeline: geometry. A still Sphere's (lua/README.md, "Entities") world-
// space bounding sphere, which the backends keep beside their references
// to it: most shadow rays a backend's box lets through pass the sphere by a
// clear margin, and this settles them without taking the ray into the
// sphere's object space (two matrix products) or reading its Entity.
#pragma once

#include "math/ray.h"
#include "math/ray_lanes.h"
#include "math/transform.h"
#include "math/vec3.h"

#include <cstdint>

namespace lray {

class SphereBound {
public:
  /// Never settles anything (a shape that is not a still sphere).
  SphereBound() = default;
  /// The unit sphere placed by `worldFromObject`.
  explicit SphereBound(const Transform &worldFromObject);

  /// True only where the line of `worldRay` passes the sphere by a clear
  /// margin, so that the sphere's own test (Sphere::intersect after
  /// shape.cpp's object ray and origin shift) finds no hit either.
  ///
  /// Why that holds: the test below reads "the line is farther from the
  /// centre than sqrt(1 + kClearMargin) R" with its rounding (at most about
  /// 16 u |oc|^2 a, u = 2^-53) inside the 1e-12 term, and R bounds the
  /// placed sphere's largest radius, so in object space the line passes
  /// more than sqrt(1 + kClearMargin) (1 - 1e-11) radii from the origin.
  /// The object ray's rounding moves it by at most about 10 u (|oc| + |c|)
  /// / r_min and turns it by 10 u kappa: with the origin within kFar radii
  /// of the centre, |c| within kFar radii of the world's origin and kappa
  /// (the transform's condition number) at most kMaxStretch, both are below
  /// 1e-6 of a radius where the line passes, far inside the margin of
  /// Sphere's own line test (1 + 1e-12 (1 + |o|^2) after the shift). A
  /// transform outside those limits gets a bound that settles nothing.
  bool missesLine(const Ray &worldRay) const {
    const Vec3 oc = worldRay.o - centre_;
    const double a = dot(worldRay.d, worldRay.d);
    const double h = dot(oc, worldRay.d);
    const double oo = dot(oc, oc);
    return oo < farSq_ && oo * a - h * h > a * radiusSq_ + 1e-12 * oo * a;
  }

  /// missesLine of *rays[0..3] at once, lane by lane the same operations
  /// (math/lanes.h): bit k set where the line of *rays[k] is settled.
  [[gnu::always_inline]] uint32_t missesLines(const Ray *const (&rays)[4]) const {
    lanes::RayLanes r;
    lanes::loadRays(rays, r);
    return missesLines(r);
  }
  /// The same for four rays already in lanes (lanes::loadRays).
  [[gnu::always_inline]] uint32_t missesLines(const lanes::RayLanes &r) const {
    using lanes::Lanes;
    Lanes farSq, radiusSq;
    lanes::splat(farSq_, farSq);
    lanes::splat(radiusSq_, radiusSq);
    const Lanes ocx = r.ox - centre_.x, ocy = r.oy - centre_.y, ocz = r.oz - centre_.z;
    const Lanes a = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz;
    const Lanes h = ocx * r.dx + ocy * r.dy + ocz * r.dz;
    const Lanes oo = ocx * ocx + ocy * ocy + ocz * ocz;
    return lanes::bits((oo < farSq) & (oo * a - h * h > a * radiusSq + 1e-12 * oo * a));
  }

  static constexpr double kClearMargin = 1e-3;
  static constexpr double kFar = 1e6;
  static constexpr double kMaxStretch = 1e3;

private:
  Vec3 centre_;
  double radiusSq_ = 0; ///< R^2 (1 + kClearMargin)
  double farSq_ = 0;    ///< (kFar r_min)^2; 0 settles nothing
};

} // namespace lray
