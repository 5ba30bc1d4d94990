// Tests for src/shading/integrator: the shading equation (lua/README.md, "The shading equation") in
// analytic configurations (lit sphere, shadow, mirror, absorbing slab, total
// internal reflection, recursion limits, area-light soft shadows), traced
// through a brute-force test accelerator.
#include "shading/integrator.h"

#include "shading/fresnel.h"

#include "shading/brute_force_accelerator.h"
#include "shading/counting_accelerator.h"
#include "shading/quad_mesh.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <unistd.h>

namespace lray {
namespace {

using testing::BruteForceAccelerator;
using testing::CountingAccelerator;
using Integ = Integrator<BruteForceAccelerator>;

const Color kRed{1, 0, 0};
const Color kSky{0.2, 0.4, 0.8};

void expectColor(const Color &a, const Color &b, double tol = 1e-9) {
  EXPECT_NEAR(a.r, b.r, tol);
  EXPECT_NEAR(a.g, b.g, tol);
  EXPECT_NEAR(a.b, b.b, tol);
}

/// Finish that only emits its ambient term.
Finish ambientOnly(double a = 1) {
  Finish f;
  f.ambient = {a, a, a};
  f.diffuse = 0;
  f.specular = 0;
  return f;
}

/// Finish that only carries light onward (no local term).
Finish dark() { return ambientOnly(0); }

struct SceneBuilder {
  Scene scene;

  uint32_t texture(const Finish &finish, const Color &color = {1, 1, 1}) {
    Pigment p;
    p.pattern = ColorPigment{color};
    scene.pigments.push_back(p);
    scene.textures.push_back({finish, static_cast<uint32_t>(scene.pigments.size() - 1)});
    return static_cast<uint32_t>(scene.textures.size() - 1);
  }
  void add(ShapeKind kind, const Transform &t, uint32_t texture) {
    Entity e;
    e.shape = makeShape(kind);
    e.worldFromObject = t;
    e.texture = texture;
    scene.entities.push_back(e);
  }
  /// A square from -1 to 1 in x and z at y = 0, normal +y, placed by t.
  void quad(const Transform &t, uint32_t texture) {
    testing::addQuad(scene, {Vec3f{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, texture, t);
  }
  void light(const Transform &t, const Color &c = {1, 1, 1}, int rows = 1, int cols = 1,
             bool area = false) {
    Light l;
    l.worldFromLight = t;
    l.color = c;
    l.rows = rows;
    l.cols = cols;
    l.area = area;
    scene.lights.push_back(l);
  }
  /// A SpotLight at `from` aimed at `at`.
  void spot(const Vec3 &from, const Vec3 &at, double angle, double falloff,
            const Color &c = {1, 1, 1}) {
    SpotLight l;
    l.worldFromLight = Transform::lookAt(
        from, at,
        std::fabs(at.x - from.x) + std::fabs(at.z - from.z) > 0 ? Vec3(0, 1, 0) : Vec3(0, 0, 1));
    l.angle = angle;
    l.falloff = falloff;
    l.color = c;
    scene.lights.push_back(l);
  }
};

struct Traced {
  Color color;
  RayCounts counts;
};

/// Parameterised over the test accelerator's shape code: false = its own
/// analytic oracle, true = the shared geometry/shape.h the backends use.
class IntegratorTest : public ::testing::TestWithParam<bool> {
protected:
  /// Traces one ray through the scene; returns its colour and the ray counts.
  Traced traceOnce(const Scene &scene, const Ray &ray, uint64_t samplerKey = 1) const {
    BruteForceAccelerator accel(scene, GetParam());
    ImageCache images(false);
    Integ integrator(scene, accel, images);
    Sampler sampler(0, samplerKey, 0);
    Traced out;
    out.color = integrator.trace(ray, sampler, out.counts);
    return out;
  }
};

Ray rayFrom(const Vec3 &o, const Vec3 &d) { return {o, d}; }

/// A tile's camera rays: kTileSide x kTileSide directions from `eye`, x
/// across [-width, width], y across [-height, height] shifted by `tilt`.
constexpr size_t kTileSide = 16, kTileRays = kTileSide * kTileSide;
std::vector<Ray> tileRays(const Vec3 &eye, double width, double height, double tilt) {
  std::vector<Ray> rays;
  for (size_t i = 0; i < kTileRays; ++i) {
    const double x = (static_cast<double>(i % kTileSide) + 0.5) / kTileSide * 2 - 1;
    const double y = (static_cast<double>(i / kTileSide) + 0.5) / kTileSide * 2 - 1;
    rays.push_back(rayFrom(eye, {x * width, y * height + tilt, 1}));
  }
  return rays;
}

TEST_P(IntegratorTest, LitSphereHeadOn) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.light(Transform::translate({0, 0, -10}));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
  // ambient 0.02 + diffuse 0.6 * N.L 1 + specular 0.1 * (R.V = 1)^1
  expectColor(r.color, {0.72, 0.72, 0.72});
  EXPECT_EQ(r.counts.shadow, 1u);
  EXPECT_EQ(r.counts.reflection + r.counts.refraction, 0u);
}

TEST_P(IntegratorTest, LitSphereObliqueWithColours) {
  SceneBuilder b;
  Finish f;
  f.exponent = 2;
  Color pigment{0.5, 1, 0.25};
  b.add(ShapeKind::Sphere, Transform(), b.texture(f, pigment));
  Color lc{1, 0.5, 0.25};
  b.light(Transform::translate({1, 0, -2}), lc);
  // Ray direction need not be unit length.
  Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 3}));
  // Hit (0,0,-1), N = -z, L = (1,0,-1)/sqrt2: N.L = 1/sqrt2; R = (-1,0,-1)/sqrt2, R.V = 1/sqrt2.
  double nl = 1 / std::sqrt(2.0), spec = 0.1 * 0.5;
  Color expected = pigment * f.ambient + lc * (pigment * (0.6 * nl) + Color(spec, spec, spec));
  expectColor(r.color, expected);
}

TEST_P(IntegratorTest, SpecularExponentIsAPower) {
  for (double e : {0.0, 1.0, 2.0, 2.5, 7.0, 64.0, 70.0}) {
    SceneBuilder b;
    Finish f = dark();
    f.specular = 0.5;
    f.exponent = e;
    b.add(ShapeKind::Sphere, Transform(), b.texture(f));
    b.light(Transform::translate({1, 0, -2}));
    // R.V = 1/sqrt2 as in the oblique test above.
    double expected = 0.5 * std::pow(std::sqrt(0.5), e);
    Color got = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1})).color;
    EXPECT_NEAR(got.r, expected, 1e-12 * std::max(1.0, expected)) << "exponent " << e;
  }
}

TEST_P(IntegratorTest, LightBehindTheSurfaceCastsNoShadowRay) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.light(Transform::translate({0, 0, 10}));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
  expectColor(r.color, {0.02, 0.02, 0.02});
  EXPECT_EQ(r.counts.shadow, 0u);
}

TEST_P(IntegratorTest, LightsDoNotFallOffWithDistance) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.light(Transform::translate({0, 0, -1000}));
  expectColor(traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1})).color, {0.72, 0.72, 0.72});
}

TEST_P(IntegratorTest, ShadowedPointGetsOnlyAmbient) {
  for (bool refractingBlocker : {false, true}) {
    SceneBuilder b;
    b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
    Finish glass = dark();
    if (refractingBlocker) {
      glass.refraction = 1;
      glass.refractionIndex = 1.5;
    }
    // Blocker on the segment from the hit (0,0,-1) to the light (-10,0,-10).
    b.add(ShapeKind::Sphere,
          Transform::translate({-5, 0, -5.5}) * Transform::scale(0.5, 0.5, 0.5), b.texture(glass));
    b.light(Transform::translate({-10, 0, -10}));
    Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
    expectColor(r.color, {0.02, 0.02, 0.02});
    EXPECT_EQ(r.counts.shadow, 1u);
  }
  // Control: without the blocker the point is lit.
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.light(Transform::translate({-10, 0, -10}));
  EXPECT_GT(traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1})).color.r, 0.3);
}

TEST_P(IntegratorTest, ShadowRayEndsAtTheLight) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  // An object beyond the light must not shadow.
  b.add(ShapeKind::Sphere, Transform::translate({0, 0, -20}), b.texture(Finish{}));
  b.light(Transform::translate({0, 0, -10}));
  expectColor(traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1})).color, {0.72, 0.72, 0.72});
}

TEST_P(IntegratorTest, MissReturnsBackgroundAndLightsAreInvisible) {
  SceneBuilder b;
  b.scene.background = kSky;
  b.light(Transform::translate({0, 0, 5}));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  expectColor(r.color, kSky);
}

TEST_P(IntegratorTest, MirrorReflectsAKnownColour) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish mirror = dark();
  mirror.reflection = 0.8;
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 5}) * Transform::scale(10, 10, 1),
        b.texture(mirror));
  b.add(ShapeKind::Sphere, Transform::translate({0, 0, -5}), b.texture(ambientOnly(), kRed));
  b.light(Transform::translate({0, 3, 0})); // no shadow ray: nothing has diffuse/specular
  Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  expectColor(r.color, kRed * 0.8);
  EXPECT_EQ(r.counts.reflection, 1u);
  EXPECT_EQ(r.counts.shadow, 0u);
}

TEST_P(IntegratorTest, ShadeHitMatchesTrace) {
  SceneBuilder b;
  Finish mirror;
  mirror.reflection = 0.5;
  b.add(ShapeKind::Sphere, Transform(), b.texture(mirror, {0.3, 0.6, 0.9}));
  b.add(ShapeKind::Sphere, Transform::translate({0, 0, -5}), b.texture(Finish{}, kRed));
  b.light(Transform::translate({2, 3, -6}), {1, 1, 1}, 2, 2, true);
  BruteForceAccelerator accel(b.scene, GetParam());
  ImageCache images(false);
  Integ integrator(b.scene, accel, images);
  Ray ray = rayFrom({0.2, 0.1, -3}, {0, 0, 1});
  Hit hit;
  ASSERT_TRUE(accel.intersect(ray, hit));
  Sampler s1(3, 4, 5), s2(3, 4, 5);
  RayCounts c1, c2;
  Color a = integrator.shadeHit(ray, hit, s1, c1);
  Color t = integrator.trace(ray, s2, c2);
  EXPECT_EQ(a, t);
  EXPECT_EQ(c1.shadow, c2.shadow);
  EXPECT_EQ(c1.reflection, 1u);
}

/// Shades a tile's hits (rays, hits, found) with copies of `samplers`
/// through shadeTile (then calls afterTile) and expects each ray's colour
/// and draws to be shadeHit's ray by ray (a miss: the background); returns
/// the tile's colours, with each way's ray counts.
template <class Accel>
std::vector<Color> expectTileMatchesRayByRay(
    const Integrator<Accel> &integrator, const std::vector<Ray> &rays,
    const std::vector<Hit> &hits, const std::vector<uint8_t> &found,
    const std::vector<Sampler> &samplers, RayCounts &tileCounts, RayCounts &rayCounts,
    const std::function<void()> &afterTile = [] {}) {
  const size_t n = rays.size();
  std::vector<Sampler> tileSamplers = samplers, raySamplers = samplers;
  std::vector<Color> tile(n);
  integrator.shadeTile(rays.data(), hits.data(), found.data(), tileSamplers.data(), n, tile.data(),
                       tileCounts);
  afterTile();
  for (size_t i = 0; i < n; ++i) {
    const Color expected = found[i] ? integrator.shadeHit(rays[i], hits[i], raySamplers[i],
                                                          rayCounts)
                                    : integrator.background();
    EXPECT_EQ(tile[i], expected) << "ray " << i;
    // Both consumed the same draws: their next ones agree.
    EXPECT_EQ(tileSamplers[i].next(), raySamplers[i].next()) << "ray " << i;
  }
  return tile;
}

/// A tile's camera rays through `scene` traced with a CountingAccelerator,
/// and the integrator to shade them, without shafts (as in a scene of more
/// than ShadowShafts::kMaxEntities): every shadow ray its occluder does not
/// settle goes to the accelerator.
struct CountedTile {
  CountedTile(const Scene &scene, bool nameBlockers, uint32_t lightShares,
              const std::vector<Ray> &rays)
      : accel(scene, nameBlockers), integrator(scene, accel, images, options(lightShares)),
        hits(rays.size()), found(rays.size()) {
    accel.intersectCoherent(rays.data(), rays.size(), hits.data(), found.data());
  }
  static IntegratorOptions options(uint32_t lightShares) {
    IntegratorOptions o;
    o.shadowSkips = false;
    o.lightShares = lightShares;
    return o;
  }
  CountingAccelerator accel;
  ImageCache images{false};
  Integrator<CountingAccelerator> integrator;
  std::vector<Hit> hits;
  std::vector<uint8_t> found;
};

/// A floor under three rows of balls, an area light of n x n cells above,
/// for tileRays({0, 1.5, -6}, 0.5, 0.3, -0.3).
SceneBuilder ballsUnderAreaLight(int n) {
  SceneBuilder b;
  b.scene.background = kSky;
  b.quad(Transform::scale(6, 1, 6) * Transform::translate({0, -1, 0}),
         b.texture(Finish{}, {0.8, 0.7, 0.6}));
  for (int i = 0; i < 24; ++i)
    b.add(ShapeKind::Sphere,
          Transform::translate({0.5 * (i % 8) - 1.75, -0.7, 0.6 * (i / 8) - 0.3}) *
              Transform::scale(0.25, 0.25, 0.25),
          b.texture(Finish{}, kRed));
  b.light(Transform::translate({-1, 5, -2}) * Transform::scale(2, 1, 2), {0.9, 0.9, 0.9}, n, n,
          true);
  return b;
}

// A tile's area-light rounds test each point's last occluder first
// (markClearLanes): a floor under three rows of balls, an area light of 4 x 4
// cells. The colours, counts and draws are the same as with no occluder
// named, and fewer shadow rays go to the accelerator.
TEST(Integrator, LastOccluderFirstGivesTheSameTile) {
  SceneBuilder b = ballsUnderAreaLight(4);
  constexpr size_t kCount = kTileRays;
  const std::vector<Ray> rays = tileRays({0, 1.5, -6}, 0.5, 0.3, -0.3);
  std::vector<Color> tiles[2];
  std::vector<uint64_t> nextDraws[2];
  RayCounts counts[2];
  size_t traced[2], blocked[2];
  for (const bool named : {false, true}) {
    CountedTile t(b.scene, named, 1, rays);
    CountingAccelerator &accel = t.accel;
    std::vector<Sampler> samplers;
    for (size_t i = 0; i < kCount; ++i) samplers.emplace_back(5, i, 0);
    tiles[named].resize(kCount);
    t.integrator.shadeTile(rays.data(), t.hits.data(), t.found.data(), samplers.data(), kCount,
                           tiles[named].data(), counts[named]);
    for (Sampler &sampler : samplers) nextDraws[named].push_back(sampler.next());
    traced[named] = accel.coherentShadowRays();
    blocked[named] = accel.blockedRays;
  }
  for (size_t i = 0; i < kCount; ++i) EXPECT_EQ(tiles[true][i], tiles[false][i]) << "ray " << i;
  EXPECT_EQ(nextDraws[true], nextDraws[false]);
  EXPECT_EQ(counts[true].shadow, counts[false].shadow);
  EXPECT_EQ(counts[true].shadowSkipped, counts[false].shadowSkipped);
  // Only blocked rays were settled by their occluder, and most of them
  // were: a point's first blocked ray names the ball, its neighbouring
  // cells' rays are blocked by it too.
  EXPECT_EQ(traced[false] - traced[true], blocked[false] - blocked[true]);
  EXPECT_GT(blocked[false], 100u);
  EXPECT_LT(blocked[true] * 4, blocked[false]);
}

/// How a call's rays group by origin: the origins they start from, and
/// whether each origin's rays are consecutive.
struct OriginRuns {
  size_t origins = 0;
  bool consecutive = true;
};
OriginRuns originRuns(const std::vector<Ray> &rays) {
  OriginRuns runs;
  std::vector<Vec3> seen;
  for (size_t k = 0; k < rays.size(); ++k) {
    if (k > 0 && rays[k].o == rays[k - 1].o) continue;
    const bool again = std::find(seen.begin(), seen.end(), rays[k].o) != seen.end();
    runs.consecutive = runs.consecutive && !again;
    if (!again) seen.push_back(rays[k].o);
  }
  runs.origins = seen.size();
  return runs;
}

// A tile's area-light rounds hold their shadow rays and trace them
// together point by point (ShadowBatch): the first round alone (its
// blockers name each point's occluder), then up to 16 rounds at once, each
// point's rays one after another. The colours and draws are shadeHit's
// ray by ray: the floor under rows of balls, an area light of 5 x 5 cells.
TEST(Integrator, AreaLightRoundsTraceTogetherPointByPoint) {
  SceneBuilder b = ballsUnderAreaLight(5);
  constexpr size_t kCount = kTileRays;
  const std::vector<Ray> rays = tileRays({0, 1.5, -6}, 0.5, 0.3, -0.3);
  // Each point's 25 cells, and spread over 3 shares (9 rounds: 1 and 8).
  for (const uint32_t shares : {1u, 3u}) {
    SCOPED_TRACE("light shares " + std::to_string(shares));
    CountedTile t(b.scene, true, shares, rays);
    std::vector<Sampler> samplers;
    for (size_t i = 0; i < kCount; ++i) {
      samplers.emplace_back(5, i, 0);
      samplers.back().lightStratum = static_cast<uint32_t>(i % 5);
    }
    RayCounts tileCounts, rayCounts;
    std::vector<std::vector<Ray>> calls; // the tile's
    expectTileMatchesRayByRay(t.integrator, rays, t.hits, t.found, samplers, tileCounts,
                              rayCounts, [&] { calls = t.accel.calls; });
    const size_t hitCount = static_cast<size_t>(std::count(t.found.begin(), t.found.end(), 1));
    EXPECT_GT(hitCount, kCount / 2);
    const size_t rounds = shares == 1 ? 25 : 9;
    ASSERT_EQ(calls.size(), shares == 1 ? 3u : 2u);
    // The first round: one ray a point, for each point that faces the light.
    const OriginRuns first = originRuns(calls[0]);
    EXPECT_EQ(first.origins, calls[0].size());
    EXPECT_GT(calls[0].size(), hitCount * 3 / 4);
    // The others: each point's rays together, several a point (fewer than
    // all its rounds', those its occluder blocked settled without a call).
    for (size_t c = 1; c < calls.size(); ++c) {
      const size_t held =
          std::min(ShadowBatch::kRounds, rounds - 1 - ShadowBatch::kRounds * (c - 1));
      const OriginRuns runs = originRuns(calls[c]);
      EXPECT_TRUE(runs.consecutive) << "call " << c;
      EXPECT_GE(runs.origins, calls[0].size() * 9 / 10) << "call " << c;
      EXPECT_GT(calls[c].size(), runs.origins * held * 3 / 4) << "call " << c;
    }
  }
}

// shadeTile batches the camera hits' shadow rays light sample by light
// sample (occludedCoherent), an area light in lanes; every colour, count
// and sampler draw must be what shadeHit gives ray by ray: a lit floor partly shadowed by spheres
// under a point light and a jittered area light, a mirror and a glass
// sphere (secondary rays with their own shadow rays), and rays that miss.
TEST_P(IntegratorTest, ShadeTileMatchesShadeHitRayByRay) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish shiny;
  shiny.specular = 0.6;
  shiny.exponent = 20;
  Finish mirror = shiny;
  mirror.reflection = 0.7;
  Finish glass = dark();
  glass.refraction = 0.9;
  glass.refractionIndex = 1.5;
  glass.absorption = 0.3;
  b.quad(Transform::scale(6, 1, 6) * Transform::translate({0, -1, 0}),
         b.texture(shiny, {0.8, 0.7, 0.6}));
  b.add(ShapeKind::Sphere, Transform::translate({-1.2, 0, 0}), b.texture(mirror, {0.3, 0.6, 0.9}));
  b.add(ShapeKind::Sphere, Transform::translate({1.2, 0, 0.5}), b.texture(glass));
  b.add(ShapeKind::Sphere, Transform::translate({0, 0.2, 2}) * Transform::scale(0.5, 0.5, 0.5),
        b.texture(Finish{}, kRed));
  b.light(Transform::translate({3, 5, -4}), {0.8, 0.8, 0.8});
  b.light(Transform::translate({-2, 4, -2}) * Transform::scale(1.5, 1, 1.5), {0.5, 0.5, 0.6}, 2,
          3, true);
  b.spot({0, 6, 0}, {0.5, 0, 0.5}, 15, 25, {0.4, 0.3, 0.2}); // lights part of the floor
  // Each light's cells in full, and spread over shares (a tile's area
  // light goes through the lanes of light_lanes.h, a lone ray's through
  // the loop one point at a time).
  for (uint32_t shares : {1u, 3u}) {
    SCOPED_TRACE("light shares " + std::to_string(shares));
    IntegratorOptions options;
    options.lightShares = shares;
    BruteForceAccelerator accel(b.scene, GetParam());
    ImageCache images(false);
    Integ integrator(b.scene, accel, images, options);

    constexpr size_t kCount = kTileRays;
    const std::vector<Ray> rays = tileRays({0, 1.5, -7}, 0.4, 0.3, -0.15);
    std::vector<Hit> hits(kCount);
    std::vector<uint8_t> found(kCount);
    accel.intersectCoherent(rays.data(), kCount, hits.data(), found.data());
    std::vector<Sampler> samplers;
    for (size_t i = 0; i < kCount; ++i) {
      samplers.emplace_back(7, i, 0);
      samplers.back().lightStratum = static_cast<uint32_t>(i % 7);
    }
    RayCounts tileCounts, rayCounts;
    const std::vector<Color> tile =
        expectTileMatchesRayByRay(integrator, rays, hits, found, samplers, tileCounts, rayCounts);
    size_t misses = 0, dark = 0;
    for (size_t i = 0; i < kCount; ++i) {
      misses += !found[i];
      dark += found[i] && tile[i].r < 0.2;
    }
    // The same shadow rays, traced or skipped by a shaft: a tile's per
    // light sample, a lone ray's per point over its area light's cells.
    EXPECT_EQ(tileCounts.shadow + tileCounts.shadowSkipped,
              rayCounts.shadow + rayCounts.shadowSkipped);
    // A lone ray's area-light cells took a shaft together and some were
    // clear (with the shared shape code: with the local shape tests
    // neither path skips a ray in this scene).
    if (GetParam()) {
      EXPECT_GT(rayCounts.shadowSkipped, 0u);
    }
    EXPECT_EQ(tileCounts.reflection, rayCounts.reflection);
    EXPECT_EQ(tileCounts.refraction, rayCounts.refraction);
    // The scene exercises what it should: misses, shadows, both secondary kinds.
    EXPECT_GT(misses, 10u);
    EXPECT_GT(dark, 5u);
    EXPECT_GT(rayCounts.shadow, (shares == 1 ? 2 : 1) * kCount);
    EXPECT_GT(rayCounts.reflection, 10u);
    EXPECT_GT(rayCounts.refraction, 10u);
  }
}

TEST_P(IntegratorTest, RefractingSlabAbsorbsAlongItsThickness) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish glass = dark();
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 0.5;
  // Slab between z = 4 and z = 6.
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 5}) * Transform::scale(40, 40, 2),
        b.texture(glass));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  expectColor(r.color, kSky * std::exp(-0.5 * 2), 1e-7);
  EXPECT_EQ(r.counts.refraction, 2u); // in, then out
  EXPECT_EQ(r.counts.reflection, 0u);

  // At 45 degrees Snell bends the ray: sin t = sin 45 / 1.5, path = 2 / cos t.
  double sinT = std::sqrt(0.5) / 1.5, cosT = std::sqrt(1 - sinT * sinT);
  Traced o = traceOnce(b.scene, rayFrom({0, 0, 0}, {1, 0, 1}));
  expectColor(o.color, kSky * std::exp(-0.5 * 2 / cosT), 1e-7);
}

TEST_P(IntegratorTest, RefractionBendsByIndexAndStraightensOnExit) {
  SceneBuilder b;
  Finish glass = dark();
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 0;
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 5}) * Transform::scale(40, 40, 2),
        b.texture(glass));
  // A red target where the exiting ray (parallel to the incoming one, shifted
  // by the slab) lands: x at exit = 4 + 2 tan t, then 45 degrees again.
  double sinT = std::sqrt(0.5) / 1.5, tanT = sinT / std::sqrt(1 - sinT * sinT);
  double xAt10 = 4 + 2 * tanT + 4;
  b.add(ShapeKind::Sphere,
        Transform::translate({xAt10, 0, 10}) * Transform::scale(0.05, 0.05, 0.05),
        b.texture(ambientOnly(), kRed));
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 0}, {1, 0, 1})).color, kRed);
  // The unbent path (index 1) would miss the target.
  b.scene.textures[0].finish.refractionIndex = 1;
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 0}, {1, 0, 1})).color, {0, 0, 0});
}

TEST_P(IntegratorTest, TotalInternalReflectionFollowsTheMirrorRay) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish glass = dark();
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 0;
  // Glass surface y = 0 with outward normal +y; rays arrive from below (inside).
  b.quad(Transform::scale(10, 1, 10), b.texture(glass));
  b.add(ShapeKind::Sphere, Transform::translate({4 * std::sin(std::numbers::pi / 3), -2, 0}) *
                               Transform::scale(0.5, 0.5, 0.5),
        b.texture(ambientOnly(), kRed));
  // 60 degrees from the normal, beyond the critical angle asin(1/1.5) = 41.8.
  Vec3 d60{std::sin(std::numbers::pi / 3), std::cos(std::numbers::pi / 3), 0};
  Traced tir = traceOnce(b.scene, rayFrom(-d60 * 2, d60));
  expectColor(tir.color, kRed);
  EXPECT_EQ(tir.counts.refraction, 0u);
  EXPECT_EQ(tir.counts.reflection, 1u);

  // 20 degrees: leaves the glass (d = 0, no absorption) to the sky.
  Vec3 d20{std::sin(std::numbers::pi / 9), std::cos(std::numbers::pi / 9), 0};
  Traced out = traceOnce(b.scene, rayFrom(-d20 * 2, d20));
  expectColor(out.color, kSky);
  EXPECT_EQ(out.counts.refraction, 1u);
  EXPECT_EQ(out.counts.reflection, 0u);

  // With fresnel, F = 1 under total internal reflection: the reflection
  // weight (1 here) takes it all, and nothing is refracted.
  b.scene.textures[0].finish.fresnel = true;
  b.scene.textures[0].finish.reflection = 1;
  Traced fresnel = traceOnce(b.scene, rayFrom(-d60 * 2, d60));
  expectColor(fresnel.color, kRed);
  EXPECT_EQ(fresnel.counts.refraction, 0u);
}

TEST_P(IntegratorTest, LeavingRayIsNotAttenuated) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish glass = dark();
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 3;
  b.quad(Transform::scale(10, 1, 10), b.texture(glass));
  // From below the surface (inside) straight out: d = 0.
  expectColor(traceOnce(b.scene, rayFrom({0, -1, 0}, {0, 1, 0})).color, kSky);
  // From above (entering) and then to the sky below: open surface, no next
  // hit, so nothing absorbs either.
  expectColor(traceOnce(b.scene, rayFrom({0, 1, 0}, {0, -1, 0})).color, kSky);
}

TEST_P(IntegratorTest, RecursionStopsAtDepth16) {
  SceneBuilder b;
  Finish mirror = ambientOnly(0.01);
  mirror.reflection = 1;
  // Two facing mirrors at z = -1.5 and z = 1.5 (cube faces).
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 2}), b.texture(mirror));
  b.add(ShapeKind::Cube, Transform::translate({0, 0, -2}), b.texture(mirror));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  EXPECT_EQ(r.counts.reflection, 16u);
  expectColor(r.color, Color(0.17, 0.17, 0.17), 1e-12); // 17 shaded hits, weight 1 each
}

TEST_P(IntegratorTest, RecursionStopsWhenTheWeightFallsBelowBailout) {
  SceneBuilder b;
  Finish mirror = dark();
  mirror.reflection = 0.5;
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 2}), b.texture(mirror));
  b.add(ShapeKind::Cube, Transform::translate({0, 0, -2}), b.texture(mirror));
  Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  // 0.5^7 = 1/128 >= 1/255 is traced; 0.5^8 = 1/256 is not.
  EXPECT_EQ(r.counts.reflection, 7u);
}

/// Floor at y = 0 (diffuse 1 only), 4x4 light of side 4 at y = 10, and a
/// blocker covering x > 0 at y = 5: exactly the cells with x > 0 are hidden
/// from the origin.
Scene softShadowScene(bool area, bool blocker) {
  SceneBuilder b;
  Finish f = dark();
  f.diffuse = 1;
  b.quad(Transform::scale(20, 1, 20), b.texture(f));
  if (blocker) {
    b.add(ShapeKind::Cube, Transform::translate({5, 5, 0}) * Transform::scale(10, 1, 10),
          b.texture(dark()));
  }
  b.light(Transform::translate({0, 10, 0}) * Transform::scale(4, 1, 4), {1, 1, 1}, 4, 4, area);
  return b.scene;
}

TEST_P(IntegratorTest, AreaLightSoftShadowFractionAtCellCentres) {
  Ray down = rayFrom({0, 1, 0}, {0, -1, 0});
  double expected = 0, unblocked = 0;
  for (double x : {-1.5, -0.5, 0.5, 1.5}) {
    for (double z : {-1.5, -0.5, 0.5, 1.5}) {
      double nl = 10 / std::sqrt(x * x + 100 + z * z);
      unblocked += nl / 16;
      if (x < 0) expected += nl / 16;
    }
  }
  Traced lit = traceOnce(softShadowScene(false, false), down);
  expectColor(lit.color, Color(1, 1, 1) * unblocked, 1e-12);
  Traced half = traceOnce(softShadowScene(false, true), down);
  expectColor(half.color, Color(1, 1, 1) * expected, 1e-12);
  EXPECT_EQ(half.counts.shadow, 16u);
}

TEST_P(IntegratorTest, LightCellsRunAlongLocalXAndZ) {
  // Blocker over x > 0.2 at y = 5 hides light-plane points with x > 0.4 from
  // the origin. cols = 2 puts samples at x = -1 and 1 (one hidden); rows = 2
  // puts both at x = 0, z = -1 and 1 (none hidden).
  auto scene = [](int rows, int cols) {
    SceneBuilder b;
    Finish f = dark();
    f.diffuse = 1;
    b.quad(Transform::scale(20, 1, 20), b.texture(f));
    b.add(ShapeKind::Cube, Transform::translate({5.2, 5, 0}) * Transform::scale(10, 1, 10),
          b.texture(dark()));
    b.light(Transform::translate({0, 10, 0}) * Transform::scale(4, 1, 4), {1, 1, 1}, rows, cols);
    return b.scene;
  };
  Ray down = rayFrom({0, 1, 0}, {0, -1, 0});
  double nl = 10 / std::sqrt(101.0);
  EXPECT_NEAR(traceOnce(scene(1, 2), down).color.r, 0.5 * nl, 1e-12);
  EXPECT_NEAR(traceOnce(scene(2, 1), down).color.r, nl, 1e-12);
}

TEST_P(IntegratorTest, JitteredAreaLightIsStratifiedAndDeterministic) {
  Ray down = rayFrom({0, 1, 0}, {0, -1, 0});
  Scene scene = softShadowScene(true, true);
  Traced a = traceOnce(scene, down, 11);
  Traced again = traceOnce(scene, down, 11);
  Traced other = traceOnce(scene, down, 12);
  EXPECT_EQ(a.color, again.color);
  EXPECT_NE(a.color, other.color);
  // Stratified: every jittered sample stays in its cell, so exactly the 8
  // cells with x < 0 contribute, each with N.L in [10/sqrt(108), 1].
  for (const Traced &t : {a, other}) {
    EXPECT_GE(t.color.r, 0.5 * 10 / std::sqrt(108.0));
    EXPECT_LE(t.color.r, 0.5);
  }
  // Averaged over many samplers the fraction of the unshadowed value is 1/2.
  Scene open = softShadowScene(true, false);
  double shadowed = 0, full = 0;
  for (uint64_t k = 0; k < 200; ++k) {
    shadowed += traceOnce(scene, down, k).color.r;
    full += traceOnce(open, down, k).color.r;
  }
  EXPECT_NEAR(shadowed / full, 0.5, 0.02);
}

TEST_P(IntegratorTest, ExtremeFinishValuesStayFinite) {
  SceneBuilder b;
  Finish f;
  f.exponent = -2; // pow(0, -2) would be inf
  f.specular = 1;
  f.absorption = 0;
  b.add(ShapeKind::Sphere, Transform(), b.texture(f));
  b.light(Transform::translate({0, 0, -10}));
  b.light(Transform::translate({10, 0, 0}));
  for (double ex : {0.0, -2.0, 1e6}) {
    b.scene.textures[0].finish.exponent = ex;
    for (Vec3 d : {Vec3(0, 0, 1), Vec3(0.1, 0.2, 1), Vec3(0.7, 0, 1)}) {
      EXPECT_TRUE(isFinite(traceOnce(b.scene, rayFrom({0, 0, -5}, d)).color));
    }
  }
}

TEST_P(IntegratorTest, ImagePigmentThroughTheCache) {
  // A 2x1 image: left texel (0.2, 0.4, 0.6) as 8-bit, right black.
  std::string path =
      (std::filesystem::temp_directory_path() /
       ("lray_integrator_image_test_" + std::to_string(GetParam()) + "_" +
        std::to_string(::getpid()) + ".png"))
          .string();
  {
    const uint8_t px[] = {51, 102, 153, 0, 0, 0};
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
  }
  SceneBuilder b;
  b.scene.images.push_back({path, {}});
  uint32_t tex = b.texture(ambientOnly());
  b.scene.pigments[b.scene.textures[tex].pigment].pattern = ImagePigment2D{};
  b.add(ShapeKind::Sphere, Transform(), tex);
  BruteForceAccelerator accel(b.scene, GetParam());
  ImageCache images(false);
  images.load(b.scene);
  std::filesystem::remove(path);
  Integ integrator(b.scene, accel, images);
  // The sphere's front point (0,0,-1) has uv (0.25, 0.5): the left texel's centre.
  Sampler sampler;
  RayCounts counts;
  Color c = integrator.trace(rayFrom({0, 0, -5}, {0, 0, 1}), sampler, counts);
  expectColor(c, {0.2, 0.4, 0.6}, 1e-6);
}

TEST_P(IntegratorTest, MissingImageIsReported) {
  SceneBuilder b;
  b.scene.images.push_back({"/nonexistent/tex.png", {"s.lua", 3}});
  BruteForceAccelerator accel(b.scene, GetParam());
  ImageCache images(false);
  EXPECT_THROW(
      {
        Integ integrator(b.scene, accel, images);
        (void)integrator;
      },
      SceneError);
}

TEST_P(IntegratorTest, SpotLightInsideItsAngleIsAPointLight) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.spot({0, 0, -10}, {0, 0, 0}, 30, 45);
  Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
  expectColor(r.color, {0.72, 0.72, 0.72}); // as LitSphereHeadOn
  EXPECT_EQ(r.counts.shadow, 1u);
}

TEST_P(IntegratorTest, SpotLightOutsideItsFalloffAddsNothingAndCastsNoShadowRay) {
  SceneBuilder b;
  b.add(ShapeKind::Sphere, Transform(), b.texture(Finish{}));
  b.spot({0, 0, -10}, {0, 0, -20}, 30, 45); // aimed away from the sphere
  Traced r = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
  expectColor(r.color, {0.02, 0.02, 0.02});
  EXPECT_EQ(r.counts.shadow, 0u);
}

TEST_P(IntegratorTest, SpotLightFadesSmoothlyBetweenAngleAndFalloff) {
  // A floor lit by a spot 5 above it, aimed straight down: a floor point at
  // distance x from the axis sees the light at theta = atan(x / 5).
  SceneBuilder b;
  b.quad(Transform::scale(20, 1, 20), b.texture(Finish{}));
  b.spot({0, 5, 0}, {0, 0, 0}, 30, 45);
  const double c30 = std::cos(std::numbers::pi / 6), c45 = std::cos(std::numbers::pi / 4);
  double previous = 1e9;
  for (double deg : {0.0, 20.0, 29.0, 32.0, 37.5, 42.0, 46.0, 50.0}) {
    double x = 5 * std::tan(deg * std::numbers::pi / 180);
    Traced r = traceOnce(b.scene, rayFrom({x, 1, 0.001}, {0, -1, 0}));
    double c = std::cos(deg * std::numbers::pi / 180), nl = 5 / std::hypot(x, 5);
    double s = std::clamp((c - c45) / (c30 - c45), 0.0, 1.0), factor = s * s * (3 - 2 * s);
    // ambient + factor * (diffuse 0.6 N.L + specular 0.1 R.V), R.V = N.L here (V = N).
    expectColor(r.color, Color(1, 1, 1) * (0.02 + factor * 0.7 * nl), 1e-6);
    EXPECT_LE(r.color.r, previous + 1e-12) << deg; // never brighter further out
    previous = r.color.r;
    EXPECT_EQ(r.counts.shadow, deg < 45 ? 1u : 0u) << deg;
  }
}

TEST_P(IntegratorTest, EmissionIsAddedOnTheEmittingSideOnly) {
  SceneBuilder b;
  b.scene.background = kSky;
  Finish lamp = dark();
  lamp.emission = {2, 1, 0.5};
  b.add(ShapeKind::Sphere, Transform(), b.texture(lamp));
  b.light(Transform::translate({0, 0, -10})); // lights nothing: no diffuse, no specular
  Traced out = traceOnce(b.scene, rayFrom({0, 0, -5}, {0, 0, 1}));
  expectColor(out.color, {2, 1, 0.5}); // seen directly: its radiance
  EXPECT_EQ(out.counts.shadow, 0u);
  // From inside the sphere the surface shows its back: nothing is emitted there.
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1})).color, {0, 0, 0});
  // A mirror sees it at its weight, like any other colour.
  Finish mirror = dark();
  mirror.reflection = 0.5;
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 5}) * Transform::scale(10, 10, 1),
        b.texture(mirror));
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 2}, {0, 0, 1})).color, {1, 0.5, 0.25});
}

TEST(Fresnel, DielectricReflectanceAtKnownAngles) {
  // Normal incidence: ((n1 - n2) / (n1 + n2))^2, either way through the boundary.
  EXPECT_NEAR(fresnelReflectance(1, 1 / 1.5), 0.04, 1e-15);
  EXPECT_NEAR(fresnelReflectance(1, 1.5), 0.04, 1e-15);
  EXPECT_NEAR(fresnelReflectance(1, 1), 0, 1e-15);
  // Brewster's angle, tan(theta) = n2 / n1: the p-polarised half vanishes,
  // F = Rs^2 / 2 with Rs = cos(2 theta).
  const double brewster = std::atan(1.5);
  const double rs = std::cos(2 * brewster);
  EXPECT_NEAR(fresnelReflectance(std::cos(brewster), 1 / 1.5), 0.5 * rs * rs, 1e-12);
  // Grazing: everything is reflected; beyond the critical angle too.
  EXPECT_NEAR(fresnelReflectance(0, 1 / 1.5), 1, 1e-12);
  EXPECT_EQ(fresnelReflectance(std::cos(60 * std::numbers::pi / 180), 1.5), 1);
  // Monotone in the angle on entering.
  double previous = 0;
  for (int deg = 0; deg <= 90; ++deg) {
    const double f = fresnelReflectance(std::cos(deg * std::numbers::pi / 180), 1 / 1.5);
    EXPECT_GE(f, previous - 1e-15) << deg;
    previous = f;
  }
}

TEST_P(IntegratorTest, FresnelSplitsReflectionAndRefraction) {
  // A glass slab seen head on: reflection F = 0.04 of a red sphere behind
  // the camera, refraction 1 - F at each of the two faces to the sky.
  SceneBuilder b;
  b.scene.background = kSky;
  Finish glass = dark();
  glass.reflection = 1;
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 0;
  glass.fresnel = true;
  b.add(ShapeKind::Cube, Transform::translate({0, 0, 5}) * Transform::scale(40, 40, 2),
        b.texture(glass));
  b.add(ShapeKind::Sphere, Transform::translate({0, 0, -5}), b.texture(ambientOnly(), kRed));
  const Traced r = traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1}));
  // In through the front (0.96), then at the back: out (0.96) to the sky,
  // or back (0.04) through the front (0.96) to the red sphere; the next
  // bounce inside weighs 0.96 * 0.04 * 0.04 < 1/255 and is not traced.
  const double f = 0.04, t = 0.96;
  expectColor(r.color, kRed * f + kSky * (t * t) + kRed * (t * f * t), 1e-12);
  // Without fresnel the same weights give mirror and refraction at full weight.
  b.scene.textures[0].finish.fresnel = false;
  b.scene.textures[0].finish.reflection = 0;
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1})).color, kSky);
  // Refraction off: fresnel scales the mirror ray alone.
  b.scene.textures[0].finish.fresnel = true;
  b.scene.textures[0].finish.reflection = 1;
  b.scene.textures[0].finish.refraction = 0;
  expectColor(traceOnce(b.scene, rayFrom({0, 0, 0}, {0, 0, 1})).color, kRed * f, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Shapes, IntegratorTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool> &param) {
                           return param.param ? "SharedShapeCode" : "LocalShapes";
                         });

} // namespace
} // namespace lray
