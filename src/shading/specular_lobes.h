// Pipeline: shading. The reflection and refraction lobes of one hit, shared
// by both integrators (lua/README.md, Finish: reflection, refraction,
// fresnel, roughness): their weights, and the directions they send a ray,
// about the surface normal for a smooth finish or about one GGX visible
// normal (shading/ggx.h) for a rough one.
#pragma once

#include "math/random.h"
#include "math/vec3.h"
#include "scene/scene.h"
#include "shading/fresnel.h"
#include "shading/ggx.h"

#include <algorithm>
#include <cmath>

namespace lray {

struct SpecularLobes {
  Vec3 facet;       ///< the normal they scatter about: N, or a microfacet's
  double kr = 0;    ///< reflection weight (times F with fresnel)
  double kt = 0;    ///< refraction weight (times 1 - F with fresnel)
  Vec3 mirror;      ///< the reflected direction
  Vec3 refracted;   ///< the refracted direction, unless totalInternal (none unless refracting)
  bool totalInternal = false; ///< (left false unless the finish refracts here)
  bool rough = false;
  double alpha = 0; ///< GGX alpha of a rough finish

  /// What a ray scattered into `next` carries, over the lobe's weight: 1
  /// for a smooth finish; for a rough one G2 / G1 (the microfacets that
  /// shadow it), 0 when `next` leaves on the wrong side of the surface
  /// (under it for a reflection, above it for a refraction).
  double throughput(const Vec3 &n, const Vec3 &dir, const Vec3 &next, bool transmitted) const {
    if (!rough) return 1;
    const double cosOut = dot(next, n);
    if (transmitted ? cosOut >= 0 : cosOut <= 0) return 0;
    return ggx::maskingShadowingOverMasking(-dot(dir, n), cosOut, alpha);
  }
};

/// The lobes of a hit seen along unit `dir` with unit normal `n` facing it
/// (dot(dir, n) <= 0), eta = n_outside / n_inside as the ray crosses. A
/// rough finish draws its microfacet from `sampler` (two numbers); a smooth
/// one draws nothing, so images without roughness keep their samples.
inline SpecularLobes specularLobes(const Vec3 &dir, const Vec3 &n, const Finish &f,
                                   bool reflects, bool refracts, double eta, Sampler &sampler) {
  SpecularLobes l;
  l.kr = reflects ? f.reflection : 0;
  l.kt = refracts ? f.refraction : 0;
  l.facet = n;
  l.rough = f.roughness > 0 && (l.kr > 0 || l.kt > 0);
  if (l.rough) {
    double u1, u2;
    sampler.next2D(u1, u2);
    l.alpha = std::max(ggx::kMinAlpha, f.roughness);
    l.facet = ggx::sampleVisibleNormal(n, -dir, l.alpha, u1, u2);
  }
  // Refracting (kt before Fresnel): else no refracted direction is asked for.
  const bool refracting = l.kt != 0;
  const double dm = dot(dir, l.facet);
  const double cosI = std::clamp(-dm, 0.0, 1.0);
  if (f.fresnel) { // F is 1 under total internal reflection: nothing is refracted
    const double fr = fresnelReflectance(cosI, eta);
    l.kr *= fr;
    l.kt *= 1 - fr;
  }
  l.mirror = dir - l.facet * (2 * dm);
  if (!refracting) return l;
  const double k = 1 - eta * eta * (1 - cosI * cosI);
  l.totalInternal = k < 0;
  if (!l.totalInternal) l.refracted = normalize(dir * eta + l.facet * (eta * cosI - std::sqrt(k)));
  return l;
}

} // namespace lray
