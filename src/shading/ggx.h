// Pipeline: shading. The GGX (Trowbridge-Reitz) microfacet distribution of
// a rough finish (lua/README.md, Finish.roughness): its normals' density D,
// Smith's masking (height-correlated, Heitz 2014, "Understanding the
// Masking-Shadowing Function in Microfacet-Based BRDFs") and the sampling
// of the normals visible from a direction (Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals"). Isotropic, alpha = roughness. Local
// functions work about +z; sampleVisibleNormal is in world space.
#pragma once

#include "math/onb.h"
#include "math/vec3.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace lray::ggx {

/// Below this alpha a rough lobe is sampled as a smooth one would be: the
/// distribution is narrower than double precision resolves.
inline constexpr double kMinAlpha = 1e-4;

/// D(m) for a microfacet normal at cos theta_m from the macro normal.
inline double density(double cosM, double alpha) {
  if (cosM <= 0) return 0;
  const double a2 = alpha * alpha, t = cosM * cosM * (a2 - 1) + 1;
  return a2 / (std::numbers::pi * t * t);
}

/// Smith's Lambda for a direction at |cos theta| from the macro normal.
inline double lambda(double cosTheta, double alpha) {
  const double c2 = cosTheta * cosTheta;
  if (c2 >= 1) return 0;
  if (c2 <= 0) return std::numeric_limits<double>::infinity();
  const double tan2 = (1 - c2) / c2;
  return (std::sqrt(1 + alpha * alpha * tan2) - 1) / 2;
}

/// The share of microfacets visible from a direction (G1).
inline double masking(double cosTheta, double alpha) { return 1 / (1 + lambda(cosTheta, alpha)); }

/// G2(o, i) / G1(o), height-correlated: what a lobe sampled by visible
/// normals multiplies its throughput by (the cosines are |cos| to the macro
/// normal, so a transmitted direction is given as it is).
inline double maskingShadowingOverMasking(double cosO, double cosI, double alpha) {
  const double lo = lambda(std::fabs(cosO), alpha), li = lambda(std::fabs(cosI), alpha);
  if (!std::isfinite(li)) return 0;
  return (1 + lo) / (1 + lo + li);
}

/// The density of visible normal m (local) seen from wo (local, z > 0):
/// G1(wo) max(0, wo.m) D(m) / wo.z.
inline double visibleNormalPdf(const Vec3 &wo, const Vec3 &m, double alpha) {
  if (wo.z <= 0) return 0;
  return masking(wo.z, alpha) * std::max(0.0, dot(wo, m)) * density(m.z, alpha) / wo.z;
}

/// A visible normal (local) seen from wo (local, z > 0) for uniform u1, u2
/// (Heitz 2018, listing 1: the hemisphere of the stretched configuration,
/// half a disk projected by the view's angle).
inline Vec3 sampleVisibleNormalLocal(const Vec3 &wo, double alpha, double u1, double u2) {
  const Vec3 vh = normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const double lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0 ? Vec3(-vh.y, vh.x, 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = cross(vh, t1);
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  const double p1 = r * std::cos(phi), s = 0.5 * (1 + vh.z);
  const double p2 = (1 - s) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + s * r * std::sin(phi);
  const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2));
  return normalize(Vec3(alpha * nh.x, alpha * nh.y, std::max(1e-12, nh.z)));
}

/// The same in world space: a microfacet normal about the macro normal n
/// visible from wo (world, dot(wo, n) > 0).
inline Vec3 sampleVisibleNormal(const Vec3 &n, const Vec3 &wo, double alpha, double u1,
                                double u2) {
  Vec3 t, b;
  orthonormalBasis(n, t, b);
  const Vec3 local(dot(wo, t), dot(wo, b), std::max(1e-12, dot(wo, n)));
  const Vec3 m = sampleVisibleNormalLocal(normalize(local), alpha, u1, u2);
  return t * m.x + b * m.y + n * m.z;
}

} // namespace lray::ggx
