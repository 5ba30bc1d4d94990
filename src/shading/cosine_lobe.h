// Pipeline: shading. The Lambertian lobe's directions (lua/README.md,
// "Light transport"): cosine-weighted about the normal, density cos / pi,
// so that the BRDF albedo / pi times cos over the density leaves the albedo.
#pragma once

#include "math/onb.h"
#include "math/vec3.h"

#include <cmath>
#include <numbers>

namespace lray {

/// A direction about unit n for uniform u1, u2 (Malley's method: a uniform
/// point of the unit disk lifted to the hemisphere); `cosTheta` gets its
/// cosine to n.
inline Vec3 sampleCosine(const Vec3 &n, double u1, double u2, double &cosTheta) {
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  cosTheta = std::sqrt(1 - u1);
  return fromBasis(n, r * std::cos(phi), r * std::sin(phi), cosTheta);
}

/// The density (solid angle) of sampleCosine's direction at cos theta.
inline double cosinePdf(double cosTheta) {
  return cosTheta > 0 ? cosTheta / std::numbers::pi : 0;
}

} // namespace lray
