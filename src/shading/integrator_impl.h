// Pipeline: shading. The definitions of integrator.h: Whitted recursion,
// the one light loop and the tile batching. Included only where the
// integrator is instantiated for a concrete backend (one translation unit
// per backend, in src/accel/, and the tests' brute-force accelerator).
#pragma once

#include "geometry/shape.h"
#include "math/lanes.h"
#include "math/spawn.h"
#include "shading/specular_lobes.h"
#include "shading/integrator.h"
#include "shading/phong.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <memory>

namespace lray {

namespace integrator_detail {

/// The emitting lights of `scene`, prepared for sampling.
inline std::vector<LightSampler> prepareLights(const Scene &scene) {
  std::vector<LightSampler> lights;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const LightMotion *motion = i < scene.lightMotion.size() ? scene.lightMotion[i].get() : nullptr;
    LightSampler s = prepareLight(scene.lights[i], motion);
    if (lightEmits(s)) lights.push_back(s); // a dark light: dropped here, not per sample
  }
  return lights;
}

} // namespace integrator_detail

template <class Accel>
Integrator<Accel>::Integrator(const Scene &scene, const Accel &accel, const ImageCache &images,
                              const IntegratorOptions &options)
    : accel_(accel), background_(scene.background),
      lights_(integrator_detail::prepareLights(scene)), materials_(scene, !lights_.empty()),
      lightShares_(std::max<uint32_t>(1, options.lightShares)),
      entities_(scene.entities.data()) {
  if (options.shadowSkips && !lights_.empty()) shafts_ = ShadowShafts(scene);
  oneShadowRay_ = lights_.size() == 1 &&
                  std::visit([](const auto &source) { return source.sampleCount(); }, lights_[0]) == 1;
  images_.reserve(scene.images.size());
  for (const ImageRef &ref : scene.images) {
    const TextureImage *image = images.find(ref.path);
    if (!image) {
      throw SceneError(ref.loc, "ImagePigment2D: image '" + ref.path + "' was not loaded");
    }
    images_.push_back(image);
  }
  pigmentTable_ = {scene.pigments.data(), scene.pigments.size(), images_.data(), images_.size()};
}

template <class Accel>
Color Integrator<Accel>::shadeHit(const Ray &ray, const Hit &hit, Sampler &sampler,
                                  RayCounts &counts) const {
  return shade(ray, hit, 0, 1.0, sampler, counts);
}

template <class Accel>
Color Integrator<Accel>::trace(const Ray &ray, Sampler &sampler, RayCounts &counts) const {
  return traceRay(ray, 0, 1.0, sampler, counts);
}

template <class Accel>
Color Integrator<Accel>::traceRay(const Ray &ray, int depth, double weight, Sampler &sampler,
                                  RayCounts &counts) const {
  Hit hit;
  if (!accel_.intersect(ray, hit)) return background_;
  return shade(ray, hit, depth, weight, sampler, counts);
}

template <class Accel>
void Integrator<Accel>::surfaceAt(const Ray &ray, const Hit &hit, Surface &s) const {
  s.m = &materials_.ofHit(hit);
  // Which side the ray arrives from is decided by the geometric normal.
  s.entering = dot(ray.d, hit.ng) < 0;
  s.n = s.entering ? hit.ns : -hit.ns;
  s.dir = normalize(ray.d);
  s.v = -s.dir;
  s.pigment = pigmentAt(pigmentTable_, s.m->pigment, hit);
}

template <class Accel>
void Integrator<Accel>::addDirectLight(const Hit *hits, const Surface *surfaces,
                                       const uint8_t *found, Sampler *samplers, size_t count,
                                       bool coherent, const LightScratch &scratch, Color *sums,
                                       RayCounts &counts) const {
  // Where each lit point's shadow rays start (of two places, by the side
  // of its surface they leave), for all the lights' samples; a point's one
  // shadow ray (one light of one cell) takes the side it needs instead.
  if (!oneShadowRay_)
    for (size_t i = 0; i < count; ++i)
      if ((!found || found[i]) && surfaces[i].m->lit) scratch.origins[i] = spawnOrigins(hits[i]);
  bool pointsInLanes = false; // scratch.lanes holds the lit points
  for (const LightSampler &light : lights_) {
    std::visit(
        [&](const auto &source) {
          using Source = std::decay_t<decltype(source)>;
          if constexpr (std::is_same_v<Source, Light::Sampler>) {
            // One cell (a point light): copying the points into lanes
            // costs more than the one round saves.
            if (scratch.lanes && coherent && !source.moves() && source.sampleCount() > 1) {
              if (!pointsInLanes) {
                scratch.lanes->clear();
                for (size_t i = 0; i < count; ++i) {
                  const Surface &s = surfaces[i];
                  if ((!found || found[i]) && s.m->lit)
                    scratch.lanes->add(static_cast<uint32_t>(i), hits[i], scratch.origins[i], s.n,
                                       s.v, s.pigment, *s.m);
                }
                pointsInLanes = true;
              }
              addLightInLanes(source, *scratch.lanes, samplers, scratch, sums, counts);
              return;
            }
          }
          // No store below aliases the light, the hits or the surfaces: the
          // sample's loop-invariant parts stay in registers.
          typename LightScratch::Pending *__restrict pending = scratch.pending;
          Ray *__restrict shadowRays = scratch.shadowRays;
          uint8_t *__restrict blocked = scratch.blocked;
          Vec3 *__restrict targets = scratch.targets;
          size_t shadow = 0;
          // Every sample of the light brings the same light (its own colour
          // need not be stored or tested per shadow ray).
          constexpr bool kUniform = Source::kUniformColor;
          const int cells = source.sampleCount();
          // Spread light sampling: this sample shades one share of the cells.
          const int shares = static_cast<int>(std::min<uint32_t>(lightShares_, cells));
          const int rounds = (cells + shares - 1) / shares;
          const double shareWeight = shares;
          // One point alone (a secondary ray's hit) takes several rounds at
          // once: its rays to the cells of an area light share an origin,
          // as coherent as a tile's to one cell, so they take a shaft and
          // a packet together. A point's draws and sums keep round order.
          const int batchRounds =
              count == 1 ? static_cast<int>(std::min<size_t>(rounds, scratch.capacity)) : 1;
          const bool coherentBatch = coherent || batchRounds > 1;
          for (int firstRound = 0; firstRound < rounds; firstRound += batchRounds) {
            // In two passes, each a short loop whose iterations overlap: the
            // light's samples (each point's sampler draws in the same order
            // as ever), then the directions and the shadow rays of those
            // that face their surface. As one loop, each sample's draw,
            // square root and division waited on the one before.
            size_t m = 0;
            const int endRound = std::min(rounds, firstRound + batchRounds);
            for (int round = firstRound; round < endRound; ++round)
              for (size_t i = 0; i < count; ++i) {
                if ((found && !found[i]) || !surfaces[i].m->lit) continue;
                int k = round;
                if (shares > 1) {
                  k = round * shares + static_cast<int>(samplers[i].lightStratum % shares);
                  if (k >= cells) continue;
                }
                const LightSample sample = source.sample(k, hits[i].p, samplers[i]);
                if constexpr (!kUniform) {
                  if (sample.color.isBlack()) continue; // outside a spot's cone
                  pending[m].dir.color = sample.color;
                }
                targets[m] = sample.target;
                pending[m].ray = static_cast<uint32_t>(i);
                ++m;
              }
            size_t n = 0; // compacted in place: n <= j
            // Sample j's direction l and cosine nl, from the light and the
            // surface: its shadow ray if it faces the light.
            auto keep = [&](size_t j, const Vec3 &l, double nl) {
              if (nl <= 0) return; // faces away: no shadow ray
              const uint32_t i = pending[j].ray;
              auto &p = pending[n];
              p.dir.l = l;
              p.dir.nl = nl;
              if constexpr (!kUniform) p.dir.color = pending[j].dir.color;
              p.ray = i;
              if (oneShadowRay_)
                spawnRayTo(hits[i], targets[j], shadowRays[n]);
              else
                spawnRayTo(scratch.origins[i], hits[i], targets[j], shadowRays[n]);
              ++n;
            };
            // Four samples at a time: the same operations as below, lane by
            // lane (the same bits), their square roots and divisions in
            // vector instructions that overlap.
            size_t first = 0;
            for (; first + lanes::kWidth <= m; first += lanes::kWidth) {
              lanes::Lanes tx, ty, tz, nx, ny, nz;
              for (int k = 0; k < lanes::kWidth; ++k) {
                const uint32_t i = pending[first + k].ray;
                const Vec3 &p = hits[i].p, &t = targets[first + k], &sn = surfaces[i].n;
                tx[k] = t.x - p.x, ty[k] = t.y - p.y, tz[k] = t.z - p.z;
                nx[k] = sn.x, ny[k] = sn.y, nz[k] = sn.z;
              }
              lanes::Lanes dist = tx * tx + ty * ty + tz * tz;
              lanes::sqrtInPlace(dist);
              const lanes::Lanes lx = tx / dist, ly = ty / dist, lz = tz / dist;
              const lanes::Lanes nl = nx * lx + ny * ly + nz * lz;
              for (int k = 0; k < lanes::kWidth; ++k)
                if (dist[k] > 0) keep(first + k, {lx[k], ly[k], lz[k]}, nl[k]);
            }
            for (; first < m; ++first) {
              const uint32_t i = pending[first].ray;
              const Vec3 toLight = targets[first] - hits[i].p;
              const double dist = length(toLight);
              if (!(dist > 0)) continue;
              const Vec3 l = toLight / dist;
              keep(first, l, dot(surfaces[i].n, l));
            }
            shadow += n;
            if (n == 0) continue;
            // Nothing between these rays' origins and ends: every one is clear.
            // Few analytic objects that may block: test those alone.
            ShadowShafts::Candidates candidates;
            if (coherentBatch && shafts_.enabled()) {
              Bounds3 from, to;
              shaftEnds(shadowRays, n, from, to);
              candidates = shafts_.candidates(from, to);
            }
            if (candidates.clear) {
              std::fill_n(blocked, n, uint8_t{0});
              shadow -= n;
              counts.shadowSkipped += n;
            } else {
              testShadowRays(candidates, shadowRays, n, coherentBatch, blocked);
            }
            for (size_t j = 0; j < n; ++j) {
              if (blocked[j]) continue;
              const auto &p = pending[j];
              const Surface &s = surfaces[p.ray];
              const Color diffuseColor = s.pigment * s.m->finish.diffuse;
              const Color &lightColor = kUniform ? source.uniformColor() : p.dir.color;
              Color lit = lightColor * phongColor(s.n, s.v, p.dir.l, p.dir.nl, diffuseColor, *s.m);
              if (shares > 1) lit = lit * shareWeight;
              sums[p.ray] += lit;
            }
          }
          counts.shadow += shadow;
        },
        light);
  }
}

template <class Accel>
void Integrator<Accel>::testShadowRays(const ShadowShafts::Candidates &candidates,
                                       const Ray *rays, size_t n, bool coherent,
                                       uint8_t *blocked) const {
  if (candidates.direct) {
    shafts_.occluded(candidates, rays, n, blocked);
  } else if (coherent) {
    accel_.occludedCoherent(rays, n, blocked, nullptr);
  } else {
    for (size_t k = 0; k < n; ++k) blocked[k] = accel_.occluded(rays[k]);
  }
}

template <class Accel>
void Integrator<Accel>::addLightInLanes(const Light::Sampler &light, LightLanes &lanes,
                                        Sampler *samplers, const LightScratch &scratch,
                                        Color *sums, RayCounts &counts) const {
  if (lanes.count == 0) return; // no lit point
  const LightGrid grid = light.grid();
  const Color &lightColor = light.uniformColor();
  for (size_t j = 0; j < lanes.count; ++j) {
    const Color &sum = sums[lanes.point[j]];
    lanes.sr[j] = sum.r, lanes.sg[j] = sum.g, lanes.sb[j] = sum.b;
  }
  std::fill_n(lanes.occluder, lanes.count, kNoEntity);
  lanes.anyOccluder = false;
  ShadowBatch &batch = *scratch.batch;
  batch.clear();
  // The jitter drawn in lanes too, unless a point's sampler is stratified.
  const bool drawInLanes = loadSamplers(lanes, samplers);
  const LaneSpan span{0, lanes.count};
  // As addDirectLight: with spread light sampling, each round a point
  // shades one cell of its share, weighted by the share count.
  const int cells = light.sampleCount();
  const int shares = static_cast<int>(std::min<uint32_t>(lightShares_, cells));
  const int rounds = (cells + shares - 1) / shares;
  const double shareWeight = shares;
  const bool batched = rounds >= static_cast<int>(ShadowBatch::kMinRounds);
  for (int round = 0; round < rounds; ++round) {
    if (shares == 1 && drawInLanes)
      placeLanes(lanes, span, light, round / light.cols(), round % light.cols());
    else
      placeSpread(lanes, span, light, round, shares, samplers, drawInLanes);
    const LightRound lit = lightLanesRound(lanes, span, grid);
    if (lit.valid != 0) {
      // As addDirectLight: nothing in the shaft, every ray is clear.
      ShadowShafts::Candidates candidates;
      if (shafts_.enabled() && lit.finite) candidates = shafts_.candidates(lit.from, lit.to);
      const uint8_t *add = lanes.valid;
      size_t waiting = 0;
      if (candidates.clear) {
        counts.shadowSkipped += lit.valid;
      } else {
        waiting = markClearLanes(lanes, span, candidates, batch, counts);
        add = lanes.clearRay;
      }
      // Settled without the accelerator, and no round before it waits:
      // its light is added now.
      if (waiting == 0 && batch.rounds == 0) addLit(lanes, span, lightColor, shareWeight, add);
      else batch.hold(lanes, span, add);
    }
    // The rounds' shadow rays are traced together (ShadowBatch), but the
    // first round's alone: what blocks them names each point's occluder
    // for the rounds after it.
    if (!batched || round == 0 || batch.full() || round + 1 == rounds)
      traceBatch(lanes, span, lightColor, shareWeight, batch);
  }
  for (size_t j = 0; j < lanes.count; ++j)
    sums[lanes.point[j]] = {lanes.sr[j], lanes.sg[j], lanes.sb[j]};
  if (drawInLanes) storeSamplers(lanes, samplers);
}

template <class Accel>
size_t Integrator<Accel>::markClearLanes(LightLanes &lanes, LaneSpan span,
                                         const ShadowShafts::Candidates &whole,
                                         ShadowBatch &batch, RayCounts &counts) const {
  Ray *__restrict rays = batch.rays + batch.count;
  uint8_t *clear = lanes.clearRay;
  // To the end of the last group of four: addLit reads flags four at a time.
  std::fill(clear + span.begin, clear + ((span.end + 3) & ~size_t{3}), uint8_t{0});
  // One analytic shape (a sphere's own points) is cheaper to test than to
  // cut the span for.
  const bool refine = shafts_.enabled() && !(whole.direct && whole.count == 1);
  const size_t step = refine ? kShaftLanes : span.end - span.begin;
  size_t n = 0; // rays for the accelerator, rays[0, n)
  for (size_t begin = span.begin; begin < span.end; begin += step) {
    const LaneSpan chunk{begin, std::min(span.end, begin + step)};
    const size_t m = lanes.writeRays(chunk, rays, n);
    if (m == 0) continue;
    ShadowShafts::Candidates candidates = whole;
    if (refine) {
      Bounds3 from, to;
      shaftEnds(rays + n, m, from, to);
      candidates = shafts_.candidates(from, to);
    }
    if (candidates.clear) {
      for (size_t k = n; k < n + m; ++k) clear[lanes.rayLane[k]] = 1;
      counts.shadowSkipped += m;
      continue;
    }
    counts.shadow += m;
    if (candidates.direct) {
      uint8_t blocked[16];
      for (size_t first = n; first < n + m; first += 16) {
        const size_t count = std::min<size_t>(16, n + m - first);
        shafts_.occluded(candidates, rays + first, count, blocked);
        for (size_t k = 0; k < count; ++k) clear[lanes.rayLane[first + k]] = !blocked[k];
      }
      continue;
    }
    if (!lanes.anyOccluder) {
      n += m; // kept
      continue;
    }
    // Kept for the accelerator (compacted in place: n <= k), but where the
    // point's last occluder blocks this ray too: a neighbouring cell's ray
    // from the same point, often blocked by the same sphere, is settled by
    // one shape test instead of a walk. The accelerator would find that
    // entity blocking the ray as well (occludedAnalytic, with the ray's
    // tMax of 1, exact in Embree's float too), so the answer is its own.
    const size_t end = n + m;
    for (size_t k = n; k < end; ++k) {
      const uint32_t lane = lanes.rayLane[k];
      const uint32_t occluder = lanes.occluder[lane];
      if (occluder != kNoEntity && occludedAnalytic(entities_[occluder], rays[k])) continue;
      if (n != k) {
        rays[n] = rays[k];
        lanes.rayLane[n] = lane;
      }
      ++n;
    }
  }
  // As the batch's next round; their lanes' flags stay 0 until it is traced.
  batch.wait(lanes, n, batch.rounds);
  return n;
}

template <class Accel>
void Integrator<Accel>::traceBatch(LightLanes &lanes, LaneSpan span, const Color &lightColor,
                                   double weight, ShadowBatch &batch) const {
  if (batch.count != 0) {
    accel_.occludedCoherent(batch.sort(), batch.count, batch.blocked, batch.blocker);
    // In the order taken: a point's last blocked ray names its occluder.
    for (size_t k = 0; k < batch.count; ++k) {
      const uint32_t at = batch.at[k], lane = batch.lane[k];
      batch.add[batch.round[k]][lane] = !batch.blocked[at];
      if (!batch.blocked[at]) continue;
      lanes.occluder[lane] = batch.blocker[at];
      lanes.anyOccluder = lanes.anyOccluder || batch.blocker[at] != kNoEntity;
    }
  }
  for (size_t r = 0; r < batch.rounds; ++r)
    addLit(lanes, span, {batch.cr[r], batch.cg[r], batch.cb[r]}, lightColor, weight,
           batch.add[r]);
  batch.clear();
}

template <class Accel>
Color Integrator<Accel>::shade(const Ray &ray, const Hit &hit, int depth, double weight,
                               Sampler &sampler, RayCounts &counts) const {
  Surface s;
  surfaceAt(ray, hit, s);
  Color c = s.pigment * s.m->finish.ambient;
  if (s.m->emits && s.entering) c += s.m->finish.emission; // seen from its emitting side
  if (s.m->lit) c += directLight(hit, s, sampler, counts);
  return addSecondary(hit, s, c, depth, weight, sampler, counts);
}

template <class Accel>
Color Integrator<Accel>::directLight(const Hit &hit, const Surface &s, Sampler &sampler,
                                     RayCounts &counts) const {
  if (!s.m->lit) return Color();
  // Room for kPointRounds of an area light's rounds at once (addDirectLight).
  PointLightScratch &scratch = threadPointLightScratch();
  Color sum;
  SpawnOrigins origins;
  addDirectLight(&hit, &s, nullptr, &sampler, 1, false,
                 {scratch.pending.data(), scratch.shadowRays.data(), scratch.blocked.data(),
                  &origins, scratch.targets.data(), nullptr, kPointRounds},
                 &sum, counts);
  return sum;
}

template <class Accel>
template <class Visit>
void Integrator<Accel>::forEachLightSample(const Vec3 &p, Sampler &sampler, Visit &&visit) const {
  for (const LightSampler &light : lights_) {
    std::visit(
        [&](const auto &source) {
          const int cells = source.sampleCount();
          const int k = cells > 1 ? std::min(cells - 1, static_cast<int>(sampler.next() * cells))
                                  : 0;
          const LightSample sample = source.sample(k, p, sampler);
          visit(sample.target, sample.color * static_cast<double>(cells));
        },
        light);
  }
}

template <class Accel>
void Integrator<Accel>::shadeTile(const Ray *rays, const Hit *hits, const uint8_t *found,
                                  Sampler *samplers, size_t count, Color *out,
                                  RayCounts &counts) const {
  assert(count <= kMaxTileRays);
  // Per-thread scratch: arrays of this size constructed on every call
  // cost the gallery scenes a measurable share of their render time
  // (bench/HISTORY.md, figures from source comments).
  TileLightScratch &scratch = threadTileLightScratch();
  auto &surface = scratch.surface;
  auto &lightSum = scratch.lightSum; // the direct light, per ray
  for (size_t i = 0; i < count; ++i) {
    if (!found[i]) continue;
    surfaceAt(rays[i], hits[i], surface[i]);
    lightSum[i] = Color();
  }
  addDirectLight(hits, surface.data(), found, samplers, count, true,
                 {scratch.pending.data(), scratch.shadowRays.data(), scratch.blocked.data(),
                  scratch.origins.data(), scratch.targets.data(), &scratch.lanes, kMaxTileRays,
                  scratch.batch.get()},
                 lightSum.data(), counts);
  for (size_t i = 0; i < count; ++i) {
    if (!found[i]) {
      out[i] = background_;
      continue;
    }
    const Surface &s = surface[i];
    Color c = s.pigment * s.m->finish.ambient;
    if (s.m->emits && s.entering) c += s.m->finish.emission;
    if (s.m->lit) c += lightSum[i];
    // addSecondary returns c itself for a surface without secondary rays:
    // most, spared the call (its colour goes by the stack both ways).
    out[i] = s.m->reflects || s.m->refracts
                 ? addSecondary(hits[i], s, c, 0, 1.0, samplers[i], counts)
                 : c;
  }
}

template <class Accel>
Color Integrator<Accel>::addSecondary(const Hit &hit, const Surface &s, Color c, int depth,
                                      double weight, Sampler &sampler, RayCounts &counts) const {
  const Material &m = *s.m;
  const Finish &f = m.finish;
  if ((!m.reflects && !m.refracts) || depth >= kMaxDepth) return c;

  // A rough finish takes one direction per lobe and pixel sample, about
  // one sampled microfacet (the paper's "glossy finishes").
  const double eta = s.entering ? 1.0 / f.refractionIndex : f.refractionIndex;
  const SpecularLobes lobes = specularLobes(s.dir, s.n, f, m.reflects, m.refracts, eta, sampler);
  double kr = lobes.kr, kt = lobes.kt;
  const Vec3 &mirrorDir = lobes.mirror;
  if (lobes.rough) {
    kr *= lobes.throughput(s.n, s.dir, mirrorDir, false);
    kt *= lobes.totalInternal ? lobes.throughput(s.n, s.dir, mirrorDir, false)
                              : lobes.throughput(s.n, s.dir, lobes.refracted, true);
  }

  if (kt > 0 && kt * weight >= kBailout) {
    if (lobes.totalInternal) {
      kr += kt; // total internal reflection: the energy follows the mirror ray
    } else {
      const Vec3 &tDir = lobes.refracted;
      Ray refracted = spawnRay(hit, tDir);
      ++counts.refraction;
      Hit next;
      Color seen = background_;
      double d = 0; // distance travelled inside the object
      if (accel_.intersect(refracted, next)) {
        seen = shade(refracted, next, depth + 1, weight * kt, sampler, counts);
        if (s.entering) d = next.t; // tDir is unit, so t is a distance
      }
      double attenuation = d > 0 ? std::exp(-std::max(0.0, f.absorption) * d) : 1.0;
      c += seen * (kt * attenuation);
    }
  }

  if (kr > 0 && kr * weight >= kBailout) {
    ++counts.reflection;
    c += traceRay(spawnRay(hit, mirrorDir), depth + 1, weight * kr, sampler, counts) * kr;
  }
  return c;
}

} // namespace lray
