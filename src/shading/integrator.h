// Pipeline: shading. The Whitted-style integrator of lua/README.md, "The
// shading equation": ambient + lights (with shadow rays) + mirror
// reflection + refraction with absorption. A template over the concrete
// accelerator (a `final` class with the member functions of
// accel/accelerator.h), so every query is a direct call; its definitions
// are in integrator_impl.h, instantiated once per backend in
// render/backends.cpp. One instance per frame; const and thread-safe while
// rendering.
#pragma once

#include "math/hit.h"
#include "math/spawn.h"
#include "math/color.h"
#include "math/random.h"
#include "math/ray.h"
#include "scene/scene.h"
#include "shading/image_cache.h"
#include "shading/integrator_options.h"
#include "shading/light_lanes.h"
#include "shading/light_scratch.h"
#include "shading/material_table.h"
#include "shading/pigment.h"
#include "shading/ray_counts.h"
#include "shading/shadow_batch.h"
#include "shading/shadow_shaft.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lray {

/// Conventions beyond lua/README.md's shading equation, all in world space:
/// - N is the shading normal flipped to the side the ray arrives from, which
///   the geometric normal decides (dot(ray.d, ng) < 0: arriving from outside,
///   entering); V = -normalize(ray.d).
/// - A light sample with N.L <= 0, or one that brings no light (outside a
///   spot's cone), adds nothing and casts no shadow ray.
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

  /// Precomputes the material table, prepared lights and resolved image
  /// pointers once per frame. `scene`, `accel` and `images` must outlive it.
  /// Throws SceneError if an image of the scene was not loaded into `images`.
  /// `options.lightShares` > 1 spreads each light's cells over a pixel's samples:
  /// a light of K cells is cut into G = min(lightShares, K) interleaved
  /// shares (cells t, t + G, t + 2G, ...); a sample shades only share
  /// `sampler.lightStratum % G`, each cell weighted G. A pixel's stratum is
  /// offset by a random amount, so every share is equally likely for every
  /// sample and the expected value is that of shading every cell (1).
  /// `options.shadowSkips`: a tile's shadow rays towards a light whose shaft
  /// no occluder meets are not traced (shadow_shaft.h; the same image).
  Integrator(const Scene &scene, const Accel &accel, const ImageCache &images,
             const IntegratorOptions &options = {});
  // Holds pointers into its own tables.
  Integrator(const Integrator &) = delete;
  Integrator &operator=(const Integrator &) = delete;

  /// Colour along a camera ray whose closest hit is `hit` (found by the
  /// caller, e.g. with a coherent query). Counts the shadow, reflection and
  /// refraction rays it traces in `counts` (the caller counts camera rays).
  Color shadeHit(const Ray &ray, const Hit &hit, Sampler &sampler, RayCounts &counts) const;

  /// Most camera rays of one shadeTile call.
  static constexpr size_t kMaxTileRays = kShadeTileRays;

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
  Color trace(const Ray &ray, Sampler &sampler, RayCounts &counts) const;

  Color background() const { return background_; }

  /// The hit whose albedo and normal --aovs records for a camera ray: the
  /// first (the path tracer follows perfect mirrors and glass instead).
  bool aovVertex(Ray &, Hit &) const { return true; }

  /// The pigment colour at a hit: the albedo a denoiser takes (--aovs).
  Color albedo(const Hit &hit) const {
    return evaluatePigment(pigmentTable_, materials_.ofHit(hit).pigment, hit);
  }

  /// What shading needs of a hit before any ray is traced (also a vertex
  /// of the path tracer, path_integrator.h).
  using Surface = HitSurface;
  /// Fills `s` in place (a Surface returned by value and then copied into
  /// shadeTile's array cost a store-forwarding stall per field).
  void surfaceAt(const Ray &ray, const Hit &hit, Surface &s) const;
  /// The light of the scene's lights at a hit, as the shading equation's
  /// sum over lights gives it (diffuse and highlight, shadow rays traced);
  /// black where the material is not lit.
  Color directLight(const Hit &hit, const Surface &s, Sampler &sampler, RayCounts &counts) const;
  /// One sample of each of the scene's lights seen from `p`, for what the
  /// shading equation does not light (the path tracer's rough lobes):
  /// visit(target, colour) with the point the shadow ray aims at and the
  /// whole light's colour (an area light's cell chosen uniformly, its
  /// colour times the cell count); black outside a spot's cone.
  template <class Visit> void forEachLightSample(const Vec3 &p, Sampler &sampler,
                                                 Visit &&visit) const;

private:
  /// Where a light sample lies as seen from a hit: the unit direction to
  /// it, N.L and the light it brings.
  using LightDir = PendingLight::Dir;
  /// The light loop's working arrays, per shadow ray of one light sample
  /// (`ray` indexes the points being lit).
  struct LightScratch {
    using Pending = PendingLight;
    Pending *pending;
    Ray *shadowRays;
    uint8_t *blocked;
    SpawnOrigins *origins; ///< per point: where its shadow rays start
    Vec3 *targets;         ///< per light sample: where it lies
    /// A tile's lit points in lanes, for the Lights that can take them
    /// (addLightInLanes); null: every light one point at a time.
    LightLanes *lanes = nullptr;
    /// Entries of pending, shadowRays, blocked and targets (at least the
    /// points lit together).
    size_t capacity = 1;
    /// With lanes: where their rounds' shadow rays wait to be traced.
    ShadowBatch *batch = nullptr;
  };

  Color traceRay(const Ray &ray, int depth, double weight, Sampler &sampler,
                 RayCounts &counts) const;
  Color shade(const Ray &ray, const Hit &hit, int depth, double weight, Sampler &sampler,
              RayCounts &counts) const;

  /// The one light loop: adds to sums[i] the direct light at each lit point
  /// i < count (found[i], if given, and its material lit), light by light
  /// and sample by sample, so every point draws from its sampler in the
  /// same order whether shaded alone or in a tile. Each sample's shadow
  /// rays go to the accelerator together: occludedCoherent when
  /// `coherent`, else occluded one by one; one point alone (count 1) takes
  /// up to scratch.capacity samples together, coherent.
  void addDirectLight(const Hit *hits, const Surface *surfaces, const uint8_t *found,
                      Sampler *samplers, size_t count, bool coherent, const LightScratch &scratch,
                      Color *sums, RayCounts &counts) const;

  /// blocked[k] for shadow rays[0, n) that a shaft did not settle as clear:
  /// against its few direct candidates alone, or the accelerator's
  /// (occludedCoherent when `coherent`).
  void testShadowRays(const ShadowShafts::Candidates &candidates, const Ray *rays, size_t n,
                      bool coherent, uint8_t *blocked) const;

  /// Lanes a shaft settles at once: a few rows of a tile's points.
  static constexpr size_t kShaftLanes = 32;
  /// lanes.clearRay[j] for the valid lanes j of `span` after a round whose
  /// shaft over the whole span was not clear (`whole`: its candidates):
  /// each kShaftLanes lanes get their own shaft, clear (no ray traced) or
  /// with a few analytic candidates (tested alone), and the rest wait in
  /// `batch` for the accelerator as its next round's (their flags 0 until
  /// it is traced), but for those that the entity last found blocking
  /// their point's rays (lanes.occluder) blocks again. Returns how many
  /// wait.
  size_t markClearLanes(LightLanes &lanes, LaneSpan span, const ShadowShafts::Candidates &whole,
                        ShadowBatch &batch, RayCounts &counts) const;
  /// Traces the batch's waiting rays together, point by point, updates
  /// lanes.occluder from what blocked them, and adds its rounds' light
  /// (lightColor, weight) in the order taken; the batch is empty after.
  void traceBatch(LightLanes &lanes, LaneSpan span, const Color &lightColor, double weight,
                  ShadowBatch &batch) const;

  /// addDirectLight's loop for a still Light of several cells (all of them
  /// or, with spread light sampling, each point's share), on lanes.count
  /// points in lanes: the same draws, rays, counts and sums, round by round,
  /// the rounds' shadow rays traced in batches (scratch.batch).
  void addLightInLanes(const Light::Sampler &light, LightLanes &lanes, Sampler *samplers,
                       const LightScratch &scratch, Color *sums, RayCounts &counts) const;

  /// shade after the ambient and direct light (`c`): adds what the
  /// reflected and refracted rays bring.
  Color addSecondary(const Hit &hit, const Surface &s, Color c, int depth, double weight,
                     Sampler &sampler, RayCounts &counts) const;

  const Accel &accel_;
  Color background_;
  PigmentTable pigmentTable_;
  std::vector<const TextureImage *> images_;
  std::vector<LightSampler> lights_; ///< the emitting lights, prepared
  MaterialTable materials_;
  uint32_t lightShares_;
  ShadowShafts shafts_;
  /// The scene's entities: a lit point's last occluder is tested on them
  /// (LightLanes::occluder).
  const Entity *entities_;
  /// One light of one cell (a point or spot light): a lit point sends one
  /// shadow ray, and its origin is pushed off to that ray's side alone.
  bool oneShadowRay_ = false;
};

} // namespace lray
