// Pipeline: shading. The Whitted-style integrator of SPEC 7: ambient +
// lights (with shadow rays) + mirror reflection + refraction with
// absorption. A template over the concrete accelerator (a `final` class with
// the member functions of accel/accelerator.h), so every query is a direct
// call. One instance per frame; const and thread-safe while rendering.
#pragma once

#include "geometry/hit.h"
#include "geometry/spawn.h"
#include "math/color.h"
#include "math/random.h"
#include "math/ray.h"
#include "scene/scene.h"
#include "shading/image_cache.h"
#include "shading/light_samples.h"
#include "shading/pigment.h"
#include "shading/ray_counts.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {

/// Conventions beyond SPEC 7, all in world space:
/// - N is the shading normal flipped to the side the ray arrives from, which
///   the geometric normal decides (dot(ray.d, ng) < 0: arriving from outside,
///   entering); V = -normalize(ray.d).
/// - A light sample with N.L <= 0 adds nothing and casts no shadow ray.
/// - A refracted ray that enters and then hits nothing (an open surface) is
///   not attenuated (d = 0); a negative absorption counts as 0.
/// - A child ray's weight is the parent's times its coefficient (reflection,
///   refraction, or both under total internal reflection), not the
///   absorption, which is known only after tracing.
template <class Accel> class Integrator {
public:
  /// Secondary rays are traced up to this depth (camera ray = depth 0).
  static constexpr int kMaxDepth = 16;
  /// A ray whose weight (product of the coefficients leading to it) would
  /// fall below this is not traced.
  static constexpr double kBailout = 1.0 / 255.0;

  /// Precomputes per-material flags, prepared lights and resolved image
  /// pointers once per frame. `scene`, `accel` and `images` must outlive it.
  /// Throws SceneError if an image of the scene was not loaded into `images`.
  Integrator(const Scene &scene, const Accel &accel, const ImageCache &images);
  // Holds pointers into its own tables.
  Integrator(const Integrator &) = delete;
  Integrator &operator=(const Integrator &) = delete;

  /// Colour along a camera ray whose closest hit is `hit` (found by the
  /// caller, e.g. with a coherent query). Counts the shadow, reflection and
  /// refraction rays it traces in `counts` (the caller counts camera rays).
  Color shadeHit(const Ray &ray, const Hit &hit, Sampler &sampler, RayCounts &counts) const {
    return shade(ray, hit, 0, 1.0, sampler, counts);
  }

  /// Most camera rays of one shadeTile call.
  static constexpr size_t kMaxTileRays = 256;

  /// shadeHit for the camera rays of a tile at once: out[i] is the colour
  /// of ray i (the background where found[i] is 0), with the same values,
  /// sampler draws and counts as shadeHit ray by ray. The camera hits'
  /// shadow rays go to the accelerator as one coherent batch per light
  /// sample (occludedCoherent: neighbouring pixels' rays to one point of a
  /// light). count <= kMaxTileRays.
  void shadeTile(const Ray *rays, const Hit *hits, const uint8_t *found, Sampler *samplers,
                 size_t count, Color *out, RayCounts &counts) const;

  /// Colour along any world-space ray: traces it (not counted) and shades
  /// the closest hit, or returns the background when it misses.
  Color trace(const Ray &ray, Sampler &sampler, RayCounts &counts) const {
    return traceRay(ray, 0, 1.0, sampler, counts);
  }

  Color background() const { return background_; }

private:
  struct Material {
    Finish finish;
    uint32_t pigment = 0;
    bool lit = false;      ///< diffuse or specular non-zero and some light exists
    bool reflects = false; ///< reflection > 0
    bool refracts = false; ///< refraction > 0
    /// The specular exponent when it is an integer in [0, 64] (the common
    /// case: powers by squaring instead of std::pow), else -1.
    int integerExponent = -1;
  };

  /// max(0, x)^e, written so that 0^e never becomes inf or NaN.
  static double specularPower(double x, const Material &m) {
    if (!(x > 0)) return m.finish.exponent == 0 ? 1.0 : 0.0;
    int n = m.integerExponent;
    if (n < 0) return std::pow(x, m.finish.exponent);
    double result = 1;
    while (n > 0) {
      if (n & 1) result *= x;
      x *= x;
      n >>= 1;
    }
    return result;
  }

  Color traceRay(const Ray &ray, int depth, double weight, Sampler &sampler,
                 RayCounts &counts) const {
    Hit hit;
    if (!accel_.intersect(ray, hit)) return background_;
    return shade(ray, hit, depth, weight, sampler, counts);
  }

  /// What shading needs of a hit before any ray is traced.
  struct Surface {
    const Material *m = nullptr;
    bool entering = false; ///< the ray arrives from the geometric normal's side
    Vec3 n, dir, v;        ///< N (facing the ray), normalize(ray.d), V
    Color pigment;
  };
  /// Fills `s` in place (a Surface returned by value and then copied into
  /// shadeTile's array cost a store-forwarding stall per field).
  void surfaceAt(const Ray &ray, const Hit &hit, Surface &s) const;

  Color shade(const Ray &ray, const Hit &hit, int depth, double weight, Sampler &sampler,
              RayCounts &counts) const;

  Color directLight(const Hit &hit, const Vec3 &n, const Vec3 &v, const Color &pigment,
                    const Material &m, Sampler &sampler, RayCounts &counts) const;

  /// Where a light sample lies as seen from a hit: its point, the unit
  /// direction to it and N.L.
  struct LightDir {
    Vec3 target, l;
    double nl;
  };
  /// Draws sample (row, col) of `light` (its jitter, for area lights, from
  /// `sampler`) and returns false when it cannot light the hit (at the hit
  /// point, or N.L <= 0: no shadow ray needed). directLight and shadeTile
  /// both take samples through it, so their draws and arithmetic agree.
  static bool lightDir(const LightSamples &light, int row, int col, const Hit &hit,
                       const Vec3 &n, Sampler &sampler, LightDir &out) {
    double fx = 0.5, fz = 0.5;
    if (light.area) {
      fx = sampler.next();
      fz = sampler.next();
    }
    out.target = light.samplePoint(row, col, fx, fz);
    Vec3 toLight = out.target - hit.p;
    double dist = length(toLight);
    if (!(dist > 0)) return false;
    out.l = toLight / dist;
    out.nl = dot(n, out.l);
    return !(out.nl <= 0); // faces away: no shadow ray needed
  }

  /// The light a sample reaching the surface unblocked adds, before the
  /// light's weighted colour: diffuse N.L plus the specular highlight.
  static Color sampleColor(const Vec3 &n, const Vec3 &v, const Vec3 &l, double nl,
                           const Color &diffuseColor, const Material &m) {
    Color c = diffuseColor * nl;
    if (m.finish.specular != 0) {
      Vec3 r = n * (2 * nl) - l;
      double s = m.finish.specular * specularPower(dot(r, v), m);
      c += Color(s, s, s);
    }
    return c;
  }

  /// shadeTile's working arrays: per ray, and per shadow ray of one light
  /// sample (`ray` indexes the tile's rays).
  struct TileScratch {
    struct Pending {
      uint32_t ray;
      LightDir dir;
    };
    std::array<Surface, kMaxTileRays> surface;
    std::array<Color, kMaxTileRays> lightSum;
    std::array<Pending, kMaxTileRays> pending;
    std::array<Ray, kMaxTileRays> shadowRays;
    std::array<uint8_t, kMaxTileRays> blocked;
  };

  /// shade after the ambient and direct light (`c`): adds what the
  /// reflected and refracted rays bring.
  Color addSecondary(const Hit &hit, const Surface &s, Color c, int depth, double weight,
                     Sampler &sampler, RayCounts &counts) const;

  const Accel &accel_;
  Color background_;
  PigmentTable pigmentTable_;
  std::vector<const TextureImage *> images_;
  std::vector<Material> materials_;       ///< per Scene::textures entry, plus a default last
  std::vector<uint32_t> entityMaterial_;  ///< per Scene::entities entry
  std::vector<LightSamples> lights_;
};

// --- implementation ---------------------------------------------------------

template <class Accel>
Integrator<Accel>::Integrator(const Scene &scene, const Accel &accel, const ImageCache &images)
    : accel_(accel), background_(scene.background) {
  images_.reserve(scene.images.size());
  for (const ImageRef &ref : scene.images) {
    const TextureImage *image = images.find(ref.path);
    if (!image) {
      throw SceneError(ref.loc, "ImagePigment2D: image '" + ref.path + "' was not loaded");
    }
    images_.push_back(image);
  }
  pigmentTable_ = {scene.pigments.data(), scene.pigments.size(), images_.data(), images_.size()};

  for (const Light &light : scene.lights) {
    // A black or empty light can never add anything: drop it here, not per sample.
    if (light.rows <= 0 || light.cols <= 0 || light.color.isBlack()) continue;
    lights_.push_back(LightSamples::fromLight(light));
  }

  auto makeMaterial = [&](const Finish &finish, uint32_t pigment) {
    Material m;
    m.finish = finish;
    m.pigment = pigment;
    m.lit = (finish.diffuse != 0 || finish.specular != 0) && !lights_.empty();
    m.reflects = finish.reflection > 0;
    m.refracts = finish.refraction > 0;
    double e = finish.exponent;
    if (e >= 0 && e <= 64 && e == std::floor(e)) {
      m.integerExponent = static_cast<int>(e);
    }
    if (!(finish.refractionIndex > 0) || !std::isfinite(finish.refractionIndex)) {
      m.finish.refractionIndex = 1; // guards the Snell ratio against 0 and NaN
    }
    return m;
  };
  materials_.reserve(scene.textures.size() + 1);
  for (const Texture &texture : scene.textures) {
    materials_.push_back(makeMaterial(texture.finish, texture.pigment));
  }
  // Fallback for an out-of-range texture index: default Finish, pigment 0
  // (or black when the table is empty, as evaluatePigment returns for it).
  materials_.push_back(makeMaterial(Finish{}, 0));
  entityMaterial_.reserve(scene.entities.size());
  for (const Entity &entity : scene.entities) {
    entityMaterial_.push_back(entity.texture < scene.textures.size()
                                  ? entity.texture
                                  : static_cast<uint32_t>(scene.textures.size()));
  }
}

template <class Accel>
Color Integrator<Accel>::directLight(const Hit &hit, const Vec3 &n, const Vec3 &v,
                                     const Color &pigment, const Material &m, Sampler &sampler,
                                     RayCounts &counts) const {
  Color sum;
  Color diffuseColor = pigment * m.finish.diffuse;
  for (const LightSamples &light : lights_) {
    for (int row = 0; row < light.rows; ++row) {
      for (int col = 0; col < light.cols; ++col) {
        LightDir d;
        if (!lightDir(light, row, col, hit, n, sampler, d)) continue;
        ++counts.shadow;
        if (accel_.occluded(spawnRayTo(hit, d.target))) continue;
        sum += light.weightedColor * sampleColor(n, v, d.l, d.nl, diffuseColor, m);
      }
    }
  }
  return sum;
}

template <class Accel>
void Integrator<Accel>::surfaceAt(const Ray &ray, const Hit &hit, Surface &s) const {
  s.m = &materials_[hit.entity < entityMaterial_.size() ? entityMaterial_[hit.entity]
                                                        : materials_.size() - 1];
  // Which side the ray arrives from is decided by the geometric normal.
  s.entering = dot(ray.d, hit.ng) < 0;
  s.n = s.entering ? hit.ns : -hit.ns;
  s.dir = normalize(ray.d);
  s.v = -s.dir;
  s.pigment = evaluatePigment(pigmentTable_, s.m->pigment, hit);
}

template <class Accel>
Color Integrator<Accel>::shade(const Ray &ray, const Hit &hit, int depth, double weight,
                               Sampler &sampler, RayCounts &counts) const {
  Surface s;
  surfaceAt(ray, hit, s);
  Color c = s.pigment * s.m->finish.ambient;
  if (s.m->lit) c += directLight(hit, s.n, s.v, s.pigment, *s.m, sampler, counts);
  return addSecondary(hit, s, c, depth, weight, sampler, counts);
}

template <class Accel>
void Integrator<Accel>::shadeTile(const Ray *rays, const Hit *hits, const uint8_t *found,
                                  Sampler *samplers, size_t count, Color *out,
                                  RayCounts &counts) const {
  assert(count <= kMaxTileRays);
  // Per-thread scratch: arrays of this size constructed on every call
  // cost the gallery scenes 2-3 % of their render time.
  static thread_local TileScratch scratch;
  auto &surface = scratch.surface;
  auto &lightSum = scratch.lightSum; // directLight's sum, per ray
  auto &pending = scratch.pending;
  auto &shadowRays = scratch.shadowRays;
  auto &blocked = scratch.blocked;
  for (size_t i = 0; i < count; ++i) {
    if (!found[i]) continue;
    surfaceAt(rays[i], hits[i], surface[i]);
    lightSum[i] = Color();
  }
  // directLight for all rays at once, light sample by light sample: the
  // same order of sampler draws and sums per ray as ray by ray.
  for (const LightSamples &light : lights_) {
    for (int row = 0; row < light.rows; ++row) {
      for (int col = 0; col < light.cols; ++col) {
        size_t n = 0;
        for (size_t i = 0; i < count; ++i) {
          if (!found[i] || !surface[i].m->lit) continue;
          auto &p = pending[n];
          if (!lightDir(light, row, col, hits[i], surface[i].n, samplers[i], p.dir)) continue;
          ++counts.shadow;
          p.ray = static_cast<uint32_t>(i);
          shadowRays[n] = spawnRayTo(hits[i], p.dir.target);
          ++n;
        }
        if (n == 0) continue;
        accel_.occludedCoherent(shadowRays.data(), n, blocked.data());
        for (size_t k = 0; k < n; ++k) {
          if (blocked[k]) continue;
          const auto &p = pending[k];
          const Surface &s = surface[p.ray];
          const Color diffuseColor = s.pigment * s.m->finish.diffuse;
          lightSum[p.ray] +=
              light.weightedColor * sampleColor(s.n, s.v, p.dir.l, p.dir.nl, diffuseColor, *s.m);
        }
      }
    }
  }
  for (size_t i = 0; i < count; ++i) {
    if (!found[i]) {
      out[i] = background_;
      continue;
    }
    const Surface &s = surface[i];
    Color c = s.pigment * s.m->finish.ambient;
    if (s.m->lit) c += lightSum[i];
    out[i] = addSecondary(hits[i], s, c, 0, 1.0, samplers[i], counts);
  }
}

template <class Accel>
Color Integrator<Accel>::addSecondary(const Hit &hit, const Surface &s, Color c, int depth,
                                      double weight, Sampler &sampler, RayCounts &counts) const {
  const Material &m = *s.m;
  const Finish &f = m.finish;
  if ((!m.reflects && !m.refracts) || depth >= kMaxDepth) return c;

  const Vec3 &n = s.n, &dir = s.dir;
  double dn = dot(dir, n);
  Vec3 mirrorDir = dir - n * (2 * dn);
  double kr = m.reflects ? f.reflection : 0;

  if (m.refracts && f.refraction * weight >= kBailout) {
    double eta = s.entering ? 1.0 / f.refractionIndex : f.refractionIndex;
    double cosI = std::clamp(-dn, 0.0, 1.0);
    double k = 1 - eta * eta * (1 - cosI * cosI);
    if (k < 0) {
      kr += f.refraction; // total internal reflection: the energy follows the mirror ray
    } else {
      Vec3 tDir = normalize(dir * eta + n * (eta * cosI - std::sqrt(k)));
      Ray refracted = spawnRay(hit, tDir);
      ++counts.refraction;
      Hit next;
      Color seen = background_;
      double d = 0; // distance travelled inside the object
      if (accel_.intersect(refracted, next)) {
        seen = shade(refracted, next, depth + 1, weight * f.refraction, sampler, counts);
        if (s.entering) d = next.t; // tDir is unit, so t is a distance
      }
      double attenuation = d > 0 ? std::exp(-std::max(0.0, f.absorption) * d) : 1.0;
      c += seen * (f.refraction * attenuation);
    }
  }

  if (kr > 0 && kr * weight >= kBailout) {
    ++counts.reflection;
    c += traceRay(spawnRay(hit, mirrorDir), depth + 1, weight * kr, sampler, counts) * kr;
  }
  return c;
}

} // namespace lray
