// Tests for src/shading/lights/spot_light.h: the cone's factor, the check
// of its angles, and a frame lit by a SpotLight through both backends and
// the brute-force accelerator, pixel for pixel the same.
#include "render/backends.h"
#include "render/renderer.h"
#include "shading/brute_force_accelerator.h"
#include "shading/image_cache.h"
#include "shading/lights/spot_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace lray {
namespace {

SpotLight spotAt(const Vec3 &from, const Vec3 &at, double angle, double falloff) {
  SpotLight s;
  s.worldFromLight = Transform::lookAt(from, at, {0, 0, 1});
  s.angle = angle;
  s.falloff = falloff;
  return s;
}

TEST(SpotLight, FactorIsOneInsideZeroBeyondAndSmoothstepBetween) {
  SpotLight::Sampler s(spotAt({0, 10, 0}, {0, 0, 0}, 20, 40));
  auto at = [&](double deg) {
    double x = 10 * std::tan(deg * std::numbers::pi / 180);
    return s.factor({x, 0, 0});
  };
  EXPECT_EQ(at(0), 1);
  EXPECT_EQ(at(19.9), 1);
  EXPECT_EQ(at(40.1), 0);
  EXPECT_EQ(at(80), 0);
  EXPECT_EQ(s.factor({0, 20, 0}), 0); // behind the light
  EXPECT_EQ(s.factor({0, 10, 0}), 0); // at the light itself
  // Halfway in cosine: smoothstep(0.5) = 0.5.
  double c = (std::cos(20 * std::numbers::pi / 180) + std::cos(40 * std::numbers::pi / 180)) / 2;
  EXPECT_NEAR(s.factor({10 * std::tan(std::acos(c)), 0, 0}), 0.5, 1e-12);
  // Strictly decreasing across the band.
  for (double deg = 20.5; deg < 40; deg += 0.5) EXPECT_LT(at(deg), at(deg - 0.5)) << deg;
  // The sample: the light's position and the colour times the factor.
  Sampler random(0, 0, 0);
  LightSample sample = s.sample(0, {0, 0, 0}, random);
  EXPECT_EQ(sample.target, Vec3(0, 10, 0));
  EXPECT_EQ(sample.color, Color(1, 1, 1));
  EXPECT_EQ(s.sampleCount(), 1);
}

TEST(SpotLight, EqualAnglesGiveAHardEdge) {
  SpotLight::Sampler s(spotAt({0, 10, 0}, {0, 0, 0}, 30, 30));
  EXPECT_EQ(s.factor({10 * std::tan(29.9 * std::numbers::pi / 180), 0, 0}), 1);
  EXPECT_EQ(s.factor({10 * std::tan(30.1 * std::numbers::pi / 180), 0, 0}), 0);
}

TEST(SpotLight, FalloffBelowAngleIsInvalid) {
  EXPECT_EQ(spotAt({0, 1, 0}, {}, 30, 45).invalid(), "");
  EXPECT_EQ(spotAt({0, 1, 0}, {}, 30, 30).invalid(), "");
  EXPECT_EQ(spotAt({0, 1, 0}, {}, 40, 20.5).invalid(),
            "SpotLight: falloff (20.5) must be at least angle (40)");
}

/// A floor plane and a sphere under a spot aimed at the sphere, plus a dim
/// point light so the area outside the cone is not black.
Scene spotScene() {
  Scene s;
  Pigment white;
  s.pigments.push_back(white);
  s.textures.push_back({Finish{}, 0});
  Entity floor;
  floor.shape = Plane{};
  s.entities.push_back(floor);
  Entity ball;
  ball.shape = Sphere{};
  ball.worldFromObject = Transform::translate({0, 1, 0});
  s.entities.push_back(ball);
  s.lights.push_back(spotAt({0, 6, -2}, {0, 0, 0}, 15, 25));
  Light dim;
  dim.color = {0.1, 0.1, 0.1};
  dim.worldFromLight = Transform::translate({-8, 8, -8});
  s.lights.push_back(dim);
  s.camera.fov = 60;
  s.camera.aspect = 4.0 / 3;
  s.camera.worldFromCamera = Transform::lookAt({0, 3, -7}, {0, 0.5, 0}, {0, 1, 0});
  return s;
}

// A template, so that the brute-force accelerator's own renderFrame is chosen for it.
template <class Accel> Film render(const Scene &scene, const Accel &accel, RayCounts &counts) {
  ImageCache images(false);
  FrameSettings settings;
  settings.width = 64;
  settings.height = 48;
  return renderFrame(scene, accel, images, settings, counts);
}

class SpotLightRender : public ::testing::TestWithParam<BackendKind> {};

TEST_P(SpotLightRender, SameFrameAsTheBruteForceAcceleratorAndAPoolOfLight) {
  Scene scene = spotScene();
  auto accel = makeAccelerator(GetParam(), scene);
  testing::BruteForceAccelerator brute(scene, true);
  RayCounts counts, bruteCounts;
  Film film = render(scene, *accel, counts);
  Film reference = render(scene, brute, bruteCounts);
  int bright = 0, dim = 0;
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      ASSERT_EQ(film.get(x, y), reference.get(x, y)) << x << ", " << y;
      double r = film.get(x, y).r;
      bright += r > 0.3;
      dim += r > 0 && r < 0.1;
    }
  EXPECT_EQ(counts.shadow, bruteCounts.shadow);
  // The pool of light and the sphere in it; the rest of the floor dim.
  EXPECT_GT(bright, 300);
  EXPECT_GT(dim, 1000);
  // Fewer shadow rays than two per camera ray: points outside the cone cast none to the spot.
  EXPECT_LT(counts.shadow, 2 * counts.camera - 500);
}

INSTANTIATE_TEST_SUITE_P(Backends, SpotLightRender,
                         ::testing::Values(BackendKind::Embree, BackendKind::KdTree),
                         [](const auto &param) { return backendName(param.param); });

} // namespace
} // namespace lray
