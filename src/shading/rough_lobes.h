// Pipeline: shading. The rough reflection and refraction lobes of a finish
// (lua/README.md, Finish.roughness) evaluated for a given pair of
// directions, as next-event estimation and multiple importance sampling
// need them: the scattering density times the cosine, and the density with
// which the path tracer's sampling (specular_lobes.h: one visible GGX
// normal, then reflection or refraction about it by their weights) draws
// that direction. Reflection is Walter et al. 2007's microfacet BRDF;
// refraction their BTDF, without the 1/eta^2 radiance scaling (the
// convention of lua/README.md, "Light transport"). The two are exactly
// what sampling gives: fcos / pdf is the throughput a sampled direction
// carries.
#pragma once

#include "math/vec3.h"
#include "scene/scene.h"
#include "shading/fresnel.h"
#include "shading/ggx.h"

#include <algorithm>
#include <cmath>

namespace lray {

class RoughLobes {
public:
  /// The lobes of finish `f` at a hit whose ray crosses with eta =
  /// n_outside / n_inside (as specularLobes takes it).
  RoughLobes(const Finish &f, bool reflects, bool refracts, double eta)
      : reflection_(reflects ? std::max(0.0, f.reflection) : 0),
        refraction_(refracts ? std::max(0.0, f.refraction) : 0),
        alpha_(std::max(ggx::kMinAlpha, f.roughness)), eta_(eta), fresnel_(f.fresnel) {}

  /// The weight with which the path tracer chooses these lobes beside the
  /// diffuse one: reflection + refraction, an upper bound of what they
  /// carry with Fresnel about any microfacet (so the choice does not
  /// depend on the microfacet, and a density can be given for any
  /// direction).
  double selectionWeight() const { return reflection_ + refraction_; }

  struct Value {
    double fcos = 0; ///< scattering density times |cos| to the normal
    double pdf = 0;  ///< solid-angle density of drawing it, given these lobes are chosen
  };

  /// The lobes for light leaving along wo towards the viewer and arriving
  /// from wi, both unit and pointing away from the surface, with n the unit
  /// normal on wo's side (dot(wo, n) > 0).
  Value evaluate(const Vec3 &n, const Vec3 &wo, const Vec3 &wi) const {
    const double cosO = dot(wo, n), cosI = dot(wi, n);
    if (!(cosO > 0) || cosI == 0) return {};
    const bool transmitted = cosI < 0;
    // The microfacet normal that turns wo into wi: the half vector, or the
    // generalized one of refraction (Walter 2007, eq. 16), on n's side.
    Vec3 h = transmitted ? wo * eta_ + wi : wo + wi;
    const double len = length(h);
    if (!(len > 0)) return {};
    h = h / len;
    if (dot(h, n) < 0) h = -h;
    const double oh = dot(wo, h), ih = dot(wi, h);
    if (!(oh > 0) || (transmitted ? ih >= 0 : ih <= 0)) return {};

    const auto [kr, kt] = weightsAbout(oh);
    if (!(kr + kt > 0)) return {};
    const double d = ggx::density(dot(h, n), alpha_);
    const double lo = ggx::lambda(cosO, alpha_), li = ggx::lambda(std::fabs(cosI), alpha_);
    if (!std::isfinite(li)) return {};
    const double g1 = 1 / (1 + lo), g2 = 1 / (1 + lo + li);
    // The visible-normal density of h and the Jacobian from h to wi.
    const double normalPdf = g1 * oh * d / cosO;
    double jacobian;
    if (!transmitted) {
      jacobian = 1 / (4 * oh);
    } else {
      const double denom = eta_ * oh + ih;
      if (!(denom * denom > 0)) return {};
      jacobian = std::fabs(ih) / (denom * denom);
    }
    const double k = transmitted ? kt : kr;
    return {k * g2 * oh * d * jacobian / cosO, k / (kr + kt) * normalPdf * jacobian};
  }

private:
  struct Weights {
    double kr, kt;
  };
  /// What reflection and refraction carry about a microfacet seen at
  /// cos theta = oh: times F and 1 - F with fresnel; under total internal
  /// reflection the refraction weight follows the mirror, as in
  /// specularLobes's sampling.
  Weights weightsAbout(double oh) const {
    double kr = reflection_, kt = refraction_;
    if (fresnel_) {
      const double fr = fresnelReflectance(oh, eta_);
      kr *= fr;
      kt *= 1 - fr;
    }
    if (1 - eta_ * eta_ * (1 - oh * oh) < 0) return {kr + kt, 0};
    return {kr, kt};
  }

  double reflection_, refraction_, alpha_, eta_;
  bool fresnel_;
};

} // namespace lray
