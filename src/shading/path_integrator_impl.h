// Pipeline: shading. The definitions of path_integrator.h. Included only
// where the path tracer is instantiated for a concrete backend
// (render/backends.cpp, and the tests' brute-force accelerator).
#pragma once

#include "math/onb.h"
#include "math/spawn.h"
#include "shading/cosine_lobe.h"
#include "shading/emitters.h"
#include "shading/rough_lobes.h"
#include "shading/specular_lobes.h"
#include "shading/integrator_impl.h"
#include "shading/path_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace lray {

template <class Accel>
PathIntegrator<Accel>::PathIntegrator(const Scene &scene, const Accel &accel,
                                      const ImageCache &images, const IntegratorOptions &options)
    : accel_(accel), local_(scene, accel, images, options), emitters_(scene),
      background_(scene.background), maxDepth_(std::max(1, options.maxDepth)),
      clamp_(options.clamp) {}

template <class Accel>
void PathIntegrator<Accel>::shadeTile(const Ray *rays, const Hit *hits, const uint8_t *found,
                                      Sampler *samplers, size_t count, Color *out,
                                      RayCounts &counts) const {
  for (size_t i = 0; i < count; ++i) {
    counts.paths += !found[i]; // a path of no surface (path() counts the others)
    out[i] = found[i] ? path(rays[i], hits[i], true, samplers[i], counts) : clamped(background_);
  }
}

template <class Accel>
Color PathIntegrator<Accel>::trace(const Ray &ray, Sampler &sampler, RayCounts &counts) const {
  Hit hit;
  const bool found = accel_.intersect(ray, hit);
  return path(ray, hit, found, sampler, counts);
}

template <class Accel> bool PathIntegrator<Accel>::aovVertex(Ray &ray, Hit &hit) const {
  using Surface = typename Integrator<Accel>::Surface;
  constexpr int kMaxFollowed = 8;
  for (int k = 0; k < kMaxFollowed; ++k) {
    Surface s;
    local_.surfaceAt(ray, hit, s);
    const Material &m = *s.m;
    const Finish &f = m.finish;
    const bool diffuse = f.diffuse > 0 && s.pigment.maxComponent() > 0;
    const bool specular = (m.reflects && f.reflection > 0) || (m.refracts && f.refraction > 0);
    if (diffuse || m.emits || f.roughness > 0 || !specular) return true;
    // Smooth: the lobes draw nothing from the sampler.
    Sampler unused;
    const double eta = s.entering ? 1.0 / f.refractionIndex : f.refractionIndex;
    const SpecularLobes lobes = specularLobes(s.dir, s.n, f, m.reflects, m.refracts, eta, unused);
    ray = spawnRay(hit, lobes.kt > lobes.kr && !lobes.totalInternal ? lobes.refracted
                                                                     : lobes.mirror);
    if (!accel_.intersect(ray, hit)) return false;
  }
  return true;
}

namespace path_detail {

/// The power heuristic (exponent 2) weight of a strategy of density `a`
/// beside one of density `b` (Veach 1997).
inline double powerHeuristic(double a, double b) {
  const double a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0;
}

/// The share of a shadow ray of length `length` ending at `target`, a point
/// on a surface, that is left out at its end: 1e-4 (pbrt-v3's shadow
/// epsilon), or more where single precision's error at the target's
/// coordinates is larger.
inline double surfaceMargin(const Vec3 &target, double length) {
  const double largest = std::max({std::fabs(target.x), std::fabs(target.y), std::fabs(target.z)});
  const double share = 64 * std::numeric_limits<float>::epsilon() * largest / length;
  return std::min(0.5, std::max(1e-4, share));
}

} // namespace path_detail

template <class Accel>
Color PathIntegrator<Accel>::path(Ray ray, Hit hit, bool found, Sampler &sampler,
                                  RayCounts &counts) const {
  using Surface = typename Integrator<Accel>::Surface;
  Color radiance, beta(1, 1, 1); // beta: the path's throughput so far
  double absorption = 0;         // of the medium the current segment crosses (0: none)
  // How the current segment was sampled: its density (solid angle, all
  // the vertex's non-specular lobes together) when from a diffuse or
  // rough lobe, which emitter sampling could also have drawn; 0 for the
  // camera ray and smooth mirror and refracted rays.
  double scatterPdf = 0;
  Vec3 from;
  ++counts.paths;
  for (int vertex = 1;; ++vertex) {
    if (!found) {
      radiance += beta * background_; // a constant environment
      break;
    }
    ++counts.pathVertices;
    // Beer's law along a segment inside an absorbing object (a segment that
    // leaves it and hits nothing is not attenuated, as in the Whitted image).
    if (absorption > 0) beta *= std::exp(-absorption * hit.t * length(ray.d));
    Surface s;
    local_.surfaceAt(ray, hit, s);
    const Material &m = *s.m;
    const Finish &f = m.finish;
    if (m.emits && s.entering) {
      double weight = 1;
      if (scatterPdf > 0) { // emitter sampling could have found this point too
        const double d2 = dot(hit.p - from, hit.p - from);
        const double cosLight = std::fabs(dot(hit.ng, s.dir));
        const double lightPdf = cosLight > 0 ? emitters_.pdfArea(hit, from) * d2 / cosLight : 0;
        weight = path_detail::powerHeuristic(scatterPdf, lightPdf);
      }
      radiance += beta * f.emission * weight;
    }
    // A path of max_depth scattering events still looks where its last one
    // sends it (above), and goes no further.
    if (vertex > maxDepth_) break;
    if (m.lit) radiance += beta * local_.directLight(hit, s, sampler, counts);

    // The lobes and their weights: Lambertian diffuse of albedo diffuse * P,
    // reflection and refraction (times F and 1 - F with fresnel).
    const Color albedo(std::max(0.0, s.pigment.r * f.diffuse),
                       std::max(0.0, s.pigment.g * f.diffuse),
                       std::max(0.0, s.pigment.b * f.diffuse));
    const double wd = (albedo.r + albedo.g + albedo.b) / 3;
    const double eta = s.entering ? 1.0 / f.refractionIndex : f.refractionIndex;
    const SpecularLobes lobes =
        specularLobes(s.dir, s.n, f, m.reflects, m.refracts, eta, sampler);
    // Smooth lobes are chosen by what they carry about N; rough ones by a
    // weight that does not depend on their microfacet (RoughLobes), so that
    // the density of any direction is known for MIS.
    const RoughLobes rough(f, m.reflects, m.refracts, eta);
    const double ks = lobes.rough ? rough.selectionWeight() : lobes.kr + lobes.kt;
    const double total = wd + ks;
    if (!(total > 0)) break;
    const Vec3 wo = -s.dir;
    // What the non-specular lobes scatter from wi towards the viewer (times
    // |cos|), and the density with which choosing a lobe and sampling it
    // draws wi.
    struct Scatter {
      Color fcos;
      double pdf = 0;
    };
    auto scatterTowards = [&](const Vec3 &wi) {
      Scatter sc;
      const double c = dot(s.n, wi);
      if (wd > 0 && c > 0) {
        sc.fcos = albedo * (c / std::numbers::pi);
        sc.pdf = wd / total * c / std::numbers::pi;
      }
      if (lobes.rough) {
        const RoughLobes::Value v = rough.evaluate(s.n, wo, wi);
        sc.fcos += Color(v.fcos, v.fcos, v.fcos);
        sc.pdf += ks / total * v.pdf;
      }
      return sc;
    };
    // Whether a shadow ray reaches `target`, a point of a light (or of an
    // emitter's surface: onSurface); insideAttenuation below adds Beer's
    // law where the direction enters an absorbing object.
    auto visible = [&](const Vec3 &target, bool onSurface) {
      Ray shadow = spawnRayTo(hit, target);
      // A point on an emitter's surface: stop short of it by more than the
      // error of a single-precision test there (Embree's triangles), else
      // the emitter shadows itself in patterns.
      if (onSurface) shadow.tMax = 1 - path_detail::surfaceMargin(target, length(shadow.d));
      ++counts.shadow;
      return !accel_.occluded(shadow);
    };
    auto insideAttenuation = [&](const Vec3 &wi, double distance) {
      const bool into = dot(s.n, wi) < 0 && s.entering;
      return into && f.absorption > 0 ? std::exp(-f.absorption * distance) : 1.0;
    };

    // The lights' light scattered by rough lobes (the shading equation above
    // lit the diffuse lobe and the highlight). A Light's colour is its
    // irradiance over pi, as a Lambertian lobe of albedo 1 sees it.
    if (lobes.rough) { // whatever m.lit says: that is about diffuse and highlight
      local_.forEachLightSample(hit.p, sampler, [&](const Vec3 &target, const Color &light) {
        if (light.isBlack()) return;
        const Vec3 toLight = target - hit.p;
        const double d = length(toLight);
        if (!(d > 0)) return;
        const Vec3 wi = toLight / d;
        const RoughLobes::Value v = rough.evaluate(s.n, wo, wi);
        if (v.fcos > 0 && visible(target, false))
          radiance += beta * light * (std::numbers::pi * v.fcos * insideAttenuation(wi, d));
      });
    }

    // Emitters sampled directly from the diffuse and rough lobes (perfectly
    // specular ones send no other direction than their own to them).
    if ((wd > 0 || lobes.rough) && !emitters_.empty()) {
      const Emitters::Sample e = emitters_.sample(hit.p, hit.time, sampler);
      const Vec3 toLight = e.p - hit.p;
      const double d2 = dot(toLight, toLight), d = std::sqrt(d2);
      const Vec3 l = toLight / d;
      const double cosLight = -dot(e.n, l);
      const Scatter sc = cosLight > 0 && e.pdfArea > 0 && d > 0 ? scatterTowards(l) : Scatter{};
      if (!sc.fcos.isBlack() && visible(e.p, true)) {
        const double lightPdf = e.pdfArea * d2 / cosLight;
        const double weight = path_detail::powerHeuristic(lightPdf, sc.pdf);
        radiance +=
            beta * sc.fcos * e.radiance * (weight / lightPdf * insideAttenuation(l, d));
      }
    }

    // One lobe, chosen with probability weight / total: the throughput
    // takes the lobe's weight over that probability.
    const double pick = sampler.next() * total;
    Vec3 next;
    scatterPdf = 0;
    if (pick < wd) {
      // Cosine-weighted about N (cosine_lobe.h): the throughput keeps the
      // albedo over the lobe's probability.
      double u1, u2, cosTheta;
      sampler.next2D(u1, u2);
      next = sampleCosine(s.n, u1, u2, cosTheta);
      beta = beta * albedo * (total / wd);
      absorption = 0;
      scatterPdf =
          lobes.rough ? scatterTowards(next).pdf : wd / total * cosTheta / std::numbers::pi;
      ++counts.diffuse;
    } else {
      // Reflection or refraction: a smooth finish picks by the weights
      // about N, a rough one by those about its microfacet (the throughput
      // then carries their sum over the weight it was chosen by).
      const double carried = lobes.kr + lobes.kt;
      const bool reflect = lobes.rough ? (pick - wd) / ks * carried < lobes.kr
                                       : pick < wd + lobes.kr;
      // Under total internal reflection the refraction weight follows the mirror.
      const bool through = !reflect && !lobes.totalInternal;
      next = through ? lobes.refracted : lobes.mirror;
      if (through) absorption = s.entering ? std::max(0.0, f.absorption) : 0;
      else absorption = s.entering ? 0 : std::max(0.0, f.absorption); // reflected inside
      const double weight = lobes.rough ? carried * total / ks : total;
      beta *= weight * lobes.throughput(s.n, s.dir, next, through);
      if (lobes.rough) scatterPdf = scatterTowards(next).pdf;
      if (reflect) ++counts.reflection;
      else ++counts.refraction;
    }
    from = hit.p;
    if (beta.isBlack()) break; // a rough lobe sent it into the surface
    if (vertex >= kRouletteFrom) {
      const double keep = std::min(1.0, beta.maxComponent());
      if (!(keep > 0) || sampler.next() >= keep) break;
      beta = beta / keep;
    }
    ray = spawnRay(hit, next);
    found = accel_.intersect(ray, hit);
  }
  return clamped(radiance);
}

} // namespace lray
