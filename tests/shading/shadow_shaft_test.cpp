// Tests for src/shading/shadow_shaft: the shaft-against-box test, a batch
// of rays against a shaft's candidates, and frames rendered with the
// shadow skips on and off, byte for byte the same on both backends, with
// rays really skipped.
#include "shading/shadow_shaft.h"

#include "geometry/shape.h"
#include "run/frame_pipeline.h"
#include "bindings/scene_script.h"
#include "shading/image_cache.h"

#include <gtest/gtest.h>

#include <random>

namespace lray {
namespace {

Bounds3 box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return {{x0, y0, z0}, {x1, y1, z1}};
}

TEST(ShadowShaft, MeetsABoxBetweenTheEndsAndNotOneBesideOrBeyond) {
  const Bounds3 floorTile = box(0, 0, 0, 1, 0, 1), light = box(4, 10, 4, 5, 10, 5);
  // Halfway along the shaft.
  EXPECT_TRUE(shaftMeetsBox(floorTile, light, box(2.2, 4.9, 2.2, 2.4, 5.1, 2.4)));
  // Beside it at the same height, above the light, below the tile.
  EXPECT_FALSE(shaftMeetsBox(floorTile, light, box(-3, 4, 2, -2, 6, 3)));
  EXPECT_FALSE(shaftMeetsBox(floorTile, light, box(4, 11, 4, 5, 12, 5)));
  EXPECT_FALSE(shaftMeetsBox(floorTile, light, box(0, -2, 0, 1, -1, 1)));
  // Inside the shaft's bounding box but off the diagonal: the hull misses
  // it where an axis-aligned box test would not.
  EXPECT_FALSE(shaftMeetsBox(floorTile, light, box(4, 0.5, 0, 5, 1.5, 1)));
  // Touching either end counts.
  EXPECT_TRUE(shaftMeetsBox(floorTile, light, box(0.5, -1, 0.5, 0.6, 0, 0.6)));
  EXPECT_TRUE(shaftMeetsBox(floorTile, light, box(4.5, 10, 4.5, 6, 11, 6)));
  // A box enclosing everything.
  EXPECT_TRUE(shaftMeetsBox(floorTile, light, box(-100, -100, -100, 100, 100, 100)));
}

// A batch of shadow rays against a shaft's candidates, a still sphere's
// tests four rays at once (occludedStillSphereLanes): every ray's answer is
// that of the backends' test of one ray against each candidate
// (occludedAnalytic), at every batch length, with spheres, a stretched
// sphere, a cube and a torus among the candidates.
TEST(ShadowShaft, ABatchOfRaysGetsEachRaysAnswer) {
  Scene scene;
  auto add = [&](Shape shape, const Transform &xf) {
    Entity e;
    e.shape = shape;
    e.worldFromObject = xf;
    scene.entities.push_back(e);
  };
  add(Sphere{}, Transform::translate({-1.5, 2, 0}));
  add(Sphere{}, Transform::translate({1.5, 2.5, 0.5}) * Transform::scale(0.5, 1.5, 0.8));
  add(Cube{}, Transform::translate({0, 3, -1.5}) * Transform::scale(0.6, 0.6, 0.6));
  add(Torus{}, Transform::translate({0.5, 1.5, 1.5}) * Transform::scale(0.7, 0.7, 0.7));
  const ShadowShafts shafts(scene);
  ShadowShafts::Candidates c;
  c.direct = true;
  c.count = 4;
  for (uint32_t i = 0; i < 4; ++i) c.entity[i] = i;

  std::mt19937_64 rng(34);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Ray> rays;
  for (int i = 0; i < 600; ++i) {
    const Vec3 from{3 * u(rng), 0, 3 * u(rng)}, to{2 * u(rng), 6, 2 * u(rng)};
    rays.push_back({from, to - from, 0, i % 9 == 0 ? 0.4 : 1.0});
  }
  int blockedCount = 0;
  size_t first = 0;
  for (size_t n : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 13u, 64u, 493u}) {
    ASSERT_LE(first + n, rays.size());
    std::vector<uint8_t> blocked(n, 9);
    shafts.occluded(c, rays.data() + first, n, blocked.data());
    for (size_t k = 0; k < n; ++k) {
      bool one = false; // one ray, one candidate at a time
      for (size_t i = 0; i < c.count; ++i)
        one = one || occludedAnalytic(scene.entities[c.entity[i]], rays[first + k]);
      ASSERT_EQ(blocked[k], one ? 1 : 0) << first + k;
      blockedCount += one;
    }
    first += n;
  }
  EXPECT_GT(blockedCount, 100);
  EXPECT_LT(blockedCount, 500);
}

// The area-light scene of the gallery on a Floor() mesh, a second point
// light and a mirror, so shafts of both kinds and secondary rays occur.
const char *kScene = R"lua(
scene_info = SceneInfo() { image_width = 128, image_height = 80, samples = 2 }
function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 128 / 80) { transform = LookAt(Vector(0, 3.5, -8), Vector(0, 0.8, 0), y) },
  }
  s:add_entity(Floor() { texture = Texture() {
    pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)), pigment2 = ColorPigment(grey(0.4)) } } })
  s:add_entity(Sphere(Translate(Vector(-1.5, 1, 0))) {
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.2, 0.2)),
                          finish = Finish() { specular = 0.5, exponent = 30, reflection = 0.3 } } })
  s:add_entity(Cube(Translate(Vector(1.2, 0.75, 0.5)) * Rotate(y, 30) * Scale(1.5)))
  s:add_entity(Torus(Translate(Vector(0.2, 0.3, -1.6))) { minor = 0.3 })
  s:add_light(Light() { rows = 4, cols = 4, area = true,
                        transform = Translate(Vector(-5, 8, -4)) * Scale(2, 1, 2) })
  s:add_light(Light() { color = grey(0.3), transform = Translate(Vector(4, 6, -3)) })
  return s
end
)lua";

TEST(ShadowShaft, SkipsChangeNoByteOnEitherBackendInAnySamplingMode) {
  SceneScript script = SceneScript::fromString(kScene, "shafts.lua");
  const SceneInfo info = script.info();
  FrameSettings fixedAll;
  FrameSettings spread;
  spread.lightSampling = LightSampling::Spread;
  FrameSettings adaptive;
  adaptive.adaptive = true;
  adaptive.adaptiveSettings.noiseThreshold = 0.05;
  adaptive.adaptiveSettings.minSamples = 4;
  adaptive.adaptiveSettings.maxSamples = 32;
  adaptive.lightSampling = LightSampling::Spread;
  for (const char *backend : {"embree", "kdtree"}) {
    for (FrameSettings sampling : {fixedAll, spread, adaptive}) {
      ImageCache images(false);
      FrameStats on, off;
      sampling.shadowSkips = true;
      const Film with = renderScriptFrame(script, info, 0, backend, images, on, nullptr, sampling);
      sampling.shadowSkips = false;
      const Film without =
          renderScriptFrame(script, info, 0, backend, images, off, nullptr, sampling);
      EXPECT_EQ(with.data(), without.data()) << backend;
      EXPECT_EQ(with.estimateData(), without.estimateData()) << backend;
      // Rays were really skipped, and every skipped ray is one the other
      // render traced.
      EXPECT_GT(on.rays.shadowSkipped, on.rays.shadow / 5) << backend;
      EXPECT_EQ(off.rays.shadowSkipped, 0u);
      EXPECT_EQ(on.rays.shadow + on.rays.shadowSkipped, off.rays.shadow) << backend;
    }
  }
}

} // namespace
} // namespace lray
