// Pipeline: geometry (internal). The rule that gives Hit::pError, the bound
// spawn.h pushes secondary ray origins off the surface by.
//
// A spawned ray can re-hit its own surface when the surface "seen" by the
// next intersection test differs from the computed hit point by more than
// the offset. The sources, all relative to the magnitudes involved:
//  - the hit point itself (o + t d snapped to the surface, or barycentric
//    interpolation), then multiplied by worldFromObject;
//  - the next test's transform of the new origin back into object space
//    (rounding of M^-1 p + its translation);
//  - the next test's own arithmetic (quadric constant term o.o - 1, the
//    triangle test's edge/normal products, about the size of the vertices);
//  - for Embree triangle hits: the ray is single precision, so its origin is
//    rounded to float, the instance transform is float and the triangle test
//    runs in float.
// Rule: with unit roundoff `eps` and safety factor `k`
//   eObject = k eps (|pObject| + shapeScale + ||M^-1||_inf |p| + |translation of M^-1|)
//   pError  = eObject R(M) + k eps (|p| + |translation of M|)
// (|.| = largest absolute component; R(M) = the largest row sum of the
// absolute entries of the linear part, its infinity norm), so an
// object-space error of at most e per component maps to at most e R(M) per
// world component, and spawn.h's offset pError * |n|_1 >= pError along the
// unit world normal clears it. (The sum of all absolute entries, used
// before, over-counts that by up to 3x.) Analytic shapes are always
// intersected in double precision (also under Embree, whose callbacks read
// the double ray), so they use eps = 2^-53, k = 64; triangles use
// eps = 2^-24, k = 3, the bound for Embree's single-precision rays (the
// kd-tree's double test is then covered too). k = 3 covers the rounding of the spawned origin to
// float (half an ulp per component), Embree's float instance transform and its float triangle test;
// measured: no self hits at any scale down to k = 0.25 (EmbreeRobustness), while k = 8 with the old
// norm pushed origins 4.8e-3 off a floor at 1e3, past an occluder 1e-3 above it, and at 1e5 into
// the objects standing on it (tests/stress, StressScaleSweep).
#pragma once

#include "math/transform.h"
#include "math/vec3.h"

#include <cmath>

namespace lray {

constexpr double kDoubleRoundoff = 0x1p-53;
constexpr double kFloatRoundoff = 0x1p-24;
constexpr double kAnalyticErrorFactor = 64;
constexpr double kTriangleErrorFactor = 3;

inline double maxAbsComponent(const Vec3 &v) {
  return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
}

/// The rule above. `pObject` and `pWorld` are the hit point in both spaces;
/// `shapeScale` the object-space size of the primitive (1 for the unit
/// analytic shapes, the largest vertex coordinate for a triangle).
/// The norms a transform contributes to the rule (Transform caches them):
/// infinity norms of the linear parts of M and M^-1, largest translation
/// components of both.
struct TransformNorms {
  double linear, inverseLinear, translation, inverseTranslation;
};

/// The rule from norms and magnitudes: `objectMagnitude` = |pObject|,
/// `worldMagnitude` = |pWorld| (largest absolute components).
inline double hitPointErrorFromNorms(const TransformNorms &n, double objectMagnitude,
                                     double worldMagnitude, double shapeScale, double eps,
                                     double k) {
  double eObject = k * eps *
                   (objectMagnitude + shapeScale + n.inverseLinear * worldMagnitude +
                    n.inverseTranslation);
  return eObject * n.linear + k * eps * (worldMagnitude + n.translation);
}

/// The rule with the transform's cached norms (math/transform.h).
inline double hitPointErrorFromMagnitudes(const Transform &worldFromObject,
                                          double objectMagnitude, double worldMagnitude,
                                          double shapeScale, double eps, double k) {
  return hitPointErrorFromNorms({worldFromObject.linearNorm(), worldFromObject.inverseLinearNorm(),
                                 worldFromObject.translationNorm(),
                                 worldFromObject.inverseTranslationNorm()},
                                objectMagnitude, worldMagnitude, shapeScale, eps, k);
}

inline double hitPointError(const Transform &worldFromObject, const Vec3 &pObject,
                            const Vec3 &pWorld, double shapeScale, double eps, double k) {
  return hitPointErrorFromMagnitudes(worldFromObject, maxAbsComponent(pObject),
                                     maxAbsComponent(pWorld), shapeScale, eps, k);
}

} // namespace lray
