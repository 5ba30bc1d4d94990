// Pipeline: shading. The path tracer of lua/README.md, "Light transport"
// (SceneInfo.integrator = "path"): at each vertex the surface's emission,
// the light of the scene's Light and SpotLight sampled as the shading
// equation samples it (and through rough lobes, rough_lobes.h), emitting
// surfaces sampled directly (emitters.h) and weighted against the paths
// that find them by bouncing (multiple importance sampling, power
// heuristic), then one scattering lobe chosen by weight (Lambertian
// diffuse, reflection and refraction, smooth or GGX-rough, with Beer
// absorption inside), until the path escapes to the background (a
// constant environment), has made max_depth scattering events or is ended
// by Russian roulette. Like Integrator, a template over the concrete
// accelerator; defined in path_integrator_impl.h, instantiated once per
// backend in render/backends.cpp.
#pragma once

#include "shading/emitters.h"
#include "shading/integrator.h"
#include "shading/integrator_options.h"

namespace lray {

template <class Accel> class PathIntegrator {
public:
  static constexpr size_t kMaxTileRays = Integrator<Accel>::kMaxTileRays;
  /// Russian roulette may end a path from this vertex on (1: the camera hit):
  /// after the third, as lua/README.md says.
  static constexpr int kRouletteFrom = 4;

  /// `scene`, `accel` and `images` must outlive it; throws SceneError as
  /// Integrator does.
  PathIntegrator(const Scene &scene, const Accel &accel, const ImageCache &images,
                 const IntegratorOptions &options = {});
  PathIntegrator(const PathIntegrator &) = delete;
  PathIntegrator &operator=(const PathIntegrator &) = delete;

  /// The radiance along each camera ray of a tile (the background where
  /// found[i] is 0); each ray draws from its own sampler, so a pixel's value
  /// does not depend on the rays it is batched with.
  void shadeTile(const Ray *rays, const Hit *hits, const uint8_t *found, Sampler *samplers,
                 size_t count, Color *out, RayCounts &counts) const;

  /// The radiance along a camera ray whose closest hit is `hit`.
  Color shadeHit(const Ray &ray, const Hit &hit, Sampler &sampler, RayCounts &counts) const {
    return path(ray, hit, true, sampler, counts);
  }

  /// The radiance along any world-space ray (traced here, not counted).
  Color trace(const Ray &ray, Sampler &sampler, RayCounts &counts) const;

  /// The pigment colour at a hit: the albedo a denoiser takes (--aovs).
  Color albedo(const Hit &hit) const { return local_.albedo(hit); }

  /// Moves `ray` and `hit` (a camera ray's first hit) on to the first
  /// vertex that is not a perfect mirror or refraction, where a denoiser
  /// wants the albedo and normal (following the stronger smooth lobe, at
  /// most 8 times); false when the ray leaves the scene on the way.
  bool aovVertex(Ray &ray, Hit &hit) const;

private:
  Color path(Ray ray, Hit hit, bool found, Sampler &sampler, RayCounts &counts) const;

  const Accel &accel_;
  /// Surfaces and the lights' direct light, exactly as the shading
  /// equation has them (so that max_depth = 1 is the Whitted image without
  /// ambient, reflection and refraction).
  Integrator<Accel> local_;
  Emitters emitters_; ///< emitting surfaces, sampled from diffuse and rough points
  Color background_;
  int maxDepth_;
  double clamp_; ///< --clamp; 0: none

  /// --clamp, as pbrt-v4's maxcomponentvalue: the sample keeps its hue.
  Color clamped(Color c) const {
    const double largest = c.maxComponent();
    return clamp_ > 0 && largest > clamp_ ? c * (clamp_ / largest) : c;
  }
};

} // namespace lray
