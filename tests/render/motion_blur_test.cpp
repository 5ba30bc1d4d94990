// Tests for motion blur from the clock (lua/README.md, "Motion blur"): a
// blurred frame matches the average of many frames rendered at single clock
// values inside its shutter (brute force), on both backends, bit for bit the
// same on both; the scenes of a shutter must match, and say where not.
#include "accel/moving_boxes.h"
#include "bindings/scene_script.h"
#include "geometry/csg_tree.h"
#include "geometry/shape.h"
#include "math/random.h"
#include "run/frame_pipeline.h"
#include "run/scene_motion.h"
#include "shading/image_cache.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace lray {
namespace {

// Everything that can move, moving as the interpolation represents exactly
// (translations and vertices linear in the clock, turns at an even rate
// about a fixed axis): a sphere sliding, a mesh spinning, a mesh whose top
// corners slide (smooth, so its normals move too), a CSG turning about its
// centre by its own transform (its parts and their checker with it), the
// camera dollying, a light sliding. Two steps are then exact,
// so brute force must agree.
const char *kScene = R"lua(
scene_info = SceneInfo() { image_width = 48, image_height = 32, samples = 16 }
function scene(clock)
  local s = Scene() {
    background_color = Color(0.1, 0.1, 0.2),
    camera = Perspective(45, 1.5) { transform = Translate(Vector(0.6 * clock, 0, 0)) *
                                                LookAt(Vector(0, 3, -8), Vector(0, 0.8, 0), y) },
  }
  s:add_entity(Floor() { texture = Texture() {
    pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)),
                                   pigment2 = ColorPigment(grey(0.3)) } } })
  s:add_entity(Sphere(Translate(Vector(-2 + 2.5 * clock, 1, 0))) {
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.2, 0.2)) } })
  s:add_entity(Floor() { transform = Translate(Vector(1.5, 1.2, 1)) * Rotate(x, -90) *
                                     Rotate(y, 150 * clock) * Scale(0.01, 0.01, 0.01),
                         texture = Texture() { pigment = ColorPigment(Color(0.2, 0.4, 0.9)) } })
  s:add_entity(Mesh() { smooth = true,
    vertices = { {-3.2, 0, 2}, {-1.8, 0, 2},
                 {-3.2 + 1.2 * clock, 1.6, 1.5}, {-1.8 + 1.2 * clock, 1.6, 2.5} },
    indices = { {1, 3, 2}, {2, 3, 4} },
    texture = Texture() { pigment = ColorPigment(Color(0.3, 0.8, 0.3)) } })
  local turn = Translate(Vector(2.6, 0.6, 2)) * Rotate(y, 100 * clock)
  s:add_entity(Difference { Cube(Scale(1.1)), Sphere(Scale(0.7)), transform = turn,
    texture = Texture() { pigment = CheckerPigment3D() {
      pigment1 = ColorPigment(Color(0.9, 0.8, 0.2)), pigment2 = ColorPigment(Color(0.2, 0.3, 0.8)) } } })
  s:add_light(Light() { transform = Translate(Vector(-5 + 6 * clock, 8, -4)) })
  return s
end
)lua";

Film render(SceneScript &script, const SceneInfo &info, const char *backend, uint32_t seed = 0) {
  ImageCache images(false);
  FrameStats stats;
  FrameSettings sampling;
  sampling.seed = seed;
  sampling.integrator = info.integrator == "path" ? IntegratorKind::Path : IntegratorKind::Whitted;
  sampling.maxDepth = info.maxDepth;
  return renderScriptFrame(script, info, 0, backend, images, stats, nullptr, sampling);
}

/// The largest |a - b| of a channel after averaging each image over 4 x 4
/// blocks (the noise of both renders mostly cancels there).
double blockDifference(const Film &a, const Film &b) {
  double largest = 0;
  for (int by = 0; by < a.height(); by += 4)
    for (int bx = 0; bx < a.width(); bx += 4) {
      Color ca, cb;
      for (int y = by; y < by + 4; ++y)
        for (int x = bx; x < bx + 4; ++x) {
          ca += a.get(x, y);
          cb += b.get(x, y);
        }
      const Color d = (ca - cb) / 16.0;
      largest = std::max({largest, std::fabs(d.r), std::fabs(d.g), std::fabs(d.b)});
    }
  return largest;
}

/// Brute force: the average of 64 single-clock frames of 4 x 4 samples
/// spread over the clock interval [0, 1], each at another seed (other
/// positions in the pixel: fixed sampling's first sample is the pixel
/// centre, so the frames' sum weights it by 1/16 only).
Film bruteForce(SceneScript &script) {
  const int kClocks = 64;
  SceneInfo single = script.info();
  single.samples = 4;
  single.frames = 2;
  std::vector<Color> sum(static_cast<size_t>(single.imageWidth) * single.imageHeight);
  std::optional<Film> average;
  for (int i = 0; i < kClocks; ++i) {
    single.startClock = (i + 0.5) / kClocks;
    single.endClock = single.startClock + 1;
    const Film f = render(script, single, "embree", static_cast<uint32_t>(i));
    if (!average) average = f;
    for (int y = 0; y < f.height(); ++y)
      for (int x = 0; x < f.width(); ++x)
        sum[static_cast<size_t>(y) * f.width() + x] += f.get(x, y);
  }
  for (int y = 0; y < average->height(); ++y)
    for (int x = 0; x < average->width(); ++x)
      average->set(x, y, sum[static_cast<size_t>(y) * average->width() + x] / kClocks);
  return *average;
}

/// How far a render blurred over the whole clock interval [0, 1] is from
/// brute force, from a second blurred render at another seed (the noise
/// floor of the comparison) and from the sharp frame at clock 0.
struct BlurDistances {
  Film blur; ///< the blurred render (Embree)
  double bruteForce, noise, sharp;
};
BlurDistances blurDistances(SceneScript &script) {
  SceneInfo blurred = script.info();
  blurred.shutter = 1;
  Film blur = render(script, blurred, "embree");
  const Film blur2 = render(script, blurred, "embree", 1000);
  const Film sharp = render(script, script.info(), "embree");
  const double bruteForceDistance = blockDifference(blur, bruteForce(script));
  const double noise = blockDifference(blur, blur2), unblurred = blockDifference(blur, sharp);
  return {std::move(blur), bruteForceDistance, noise, unblurred};
}

TEST(MotionBlur, MatchesTheAverageOfFramesAtClocksInsideTheShutter) {
  SceneScript script = SceneScript::fromString(kScene, "blur.lua");
  const BlurDistances d = blurDistances(script);
  // Measured: brute force 0.0030, two blurred renders 0.0035, the sharp
  // frame 0.30; turns not interpolated (each half of the shutter at one
  // end's angle) gave 0.025, the CSG's pattern left where it is at the
  // shutter's opening 0.026.
  EXPECT_LT(d.bruteForce, 2 * d.noise) << "noise " << d.noise;
  EXPECT_GT(d.sharp, 20 * d.bruteForce) << "the test could not tell a sharp frame";
}

// Emitters that move, under the path tracer: each sampled where it is at
// the path's time (shading/emitters.h). A sphere sliding (sampled by the
// cone it fills), a quad turning by its transform, a triangle whose
// corner slides, over a floor they light.
const char *kGlowScene = R"lua(
scene_info = SceneInfo() { image_width = 32, image_height = 24, samples = 16,
                           integrator = "path", max_depth = 2 }
local function glow(c)
  return Texture() { pigment = ColorPigment(grey(0)),
                     finish = Finish() { diffuse = 0, emission = c } }
end
function scene(clock)
  local s = Scene() {
    camera = Perspective(50, 4 / 3) { transform = LookAt(Vector(0, 4, -6), Vector(0, 0, 0.5), y) },
  }
  s:add_entity(Floor() { texture = Texture() { pigment = ColorPigment(grey(0.8)) } })
  s:add_entity(Sphere(Translate(Vector(-2.5 + 4 * clock, 0.6, 0)) * Scale(0.3)) {
    texture = glow(Color(6, 3, 1)) })
  s:add_entity(Mesh() { transform = Translate(Vector(1.5, 1.2, 2)) * Rotate(y, 120 * clock),
    vertices = { {-0.6, 0, -0.6}, {0.6, 0, -0.6}, {-0.6, 0, 0.6}, {0.6, 0, 0.6} },
    indices = { {1, 3, 2}, {2, 3, 4} }, texture = glow(Color(1, 2, 4)) })
  s:add_entity(Mesh() { vertices = { {-2, 1.5, 2}, {-1, 1.5, 2}, {-2 + 2 * clock, 1.5, 3} },
    indices = { {1, 3, 2} }, texture = glow(Color(2, 5, 2)) })
  return s
end
)lua";

TEST(MotionBlur, PathTracedMovingEmittersMatchTheAverageOfFrames) {
  SceneScript script = SceneScript::fromString(kGlowScene, "glow.lua");
  const BlurDistances d = blurDistances(script);
  // Measured: brute force 0.025, two blurred renders 0.026, the sharp
  // frame 1.76; emitters sampled where they are at the shutter's opening
  // (as before they could move) gave 0.21.
  EXPECT_LT(d.bruteForce, 2 * d.noise) << "noise " << d.noise;
  EXPECT_GT(d.sharp, 5 * d.bruteForce) << "the test could not tell a sharp frame";
  // Both backends, the same bytes.
  SceneInfo blurred = script.info();
  blurred.shutter = 1;
  EXPECT_EQ(render(script, blurred, "kdtree").data(), d.blur.data());
}

TEST(MotionBlur, BothBackendsAndAnyThreadCountGiveTheSameBytesAndShutterZeroNoBlur) {
  SceneScript script = SceneScript::fromString(kScene, "blur.lua");
  SceneInfo info = script.info();
  info.samples = 3;
  info.shutter = 0.5;
  info.motionSteps = 3;
  const Film embree = render(script, info, "embree");
  const Film kdtree = render(script, info, "kdtree");
  EXPECT_EQ(embree.data(), kdtree.data());
  {
    // Each sample's time comes from its pixel and index: any thread count.
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(render(script, info, "kdtree").data(), embree.data());
  }

  // Shutter 0: the frame at its clock, the same as without the feature.
  info.shutter = 0;
  const Film closed = render(script, info, "embree");
  int calls = 0;
  const Scene scene = buildFrameScene(script, info, 0, calls);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(scene.motionSteps, 0);
  EXPECT_NE(closed.data(), embree.data());
}

/// kScene's frame 0 with the given shutter and motion steps, folded;
/// `calls`: how many times scene(clock) ran.
Scene foldedScene(double shutter, int steps, int &calls) {
  SceneScript script = SceneScript::fromString(kScene, "blur.lua");
  SceneInfo info = script.info();
  info.shutter = shutter;
  info.motionSteps = steps;
  calls = 0;
  return buildFrameScene(script, info, 0, calls);
}

TEST(MotionBlur, OnlyWhatMovesGetsAMotion) {
  int calls = 0;
  const Scene scene = foldedScene(0.5, 4, calls);
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(scene.motionSteps, 4);
  SceneInfo info;
  info.shutter = 0.5;
  info.motionSteps = 4;
  EXPECT_EQ(motionClocks(info, 0), (std::vector<double>{0, 0.5 / 3, 1.0 / 3, 0.5}));
  ASSERT_EQ(scene.entities.size(), 5u);
  // The CSG: its parts move, each by its own placement.
  const CsgTree &csg = *std::get<Csg>(scene.entities[4].shape).tree;
  EXPECT_TRUE(csg.leaves[0].entity.motion);
  EXPECT_TRUE(csg.leaves[1].entity.motion);
  EXPECT_TRUE(csg.leaves[0].textureMotion); // its pattern turns with the node
  EXPECT_FALSE(scene.entities[0].motion); // the floor stays
  ASSERT_TRUE(scene.entities[1].motion);
  EXPECT_EQ(scene.entities[1].motion->stepCount(), 4u);
  EXPECT_TRUE(scene.entities[2].motion);
  EXPECT_FALSE(scene.entities[2].vertexMotion);
  EXPECT_FALSE(scene.entities[3].motion);
  ASSERT_TRUE(scene.entities[3].vertexMotion);
  EXPECT_NEAR(scene.entities[3].vertexMotion->position(2, 1).x, -3.2 + 1.2 * 0.5, 1e-6);
  EXPECT_TRUE(scene.camera.motion);
  ASSERT_EQ(scene.lightMotion.size(), 1u);
  ASSERT_TRUE(scene.lightMotion[0]);
  EXPECT_NEAR(scene.lightMotion[0]->at(1).x, 3, 1e-12);
}

// The backends' test of a ray against a moving entity's bounds at the
// ray's time (accel/moving_boxes.h) must never turn away a ray that
// hits it, and should turn away some that do not.
TEST(MotionBlur, AMovingEntitysBoundsAtARaysTimeHoldEveryHit) {
  int calls = 0;
  const Scene scene = foldedScene(1, 3, calls);
  const MovingBoxes boxes(scene);
  Sampler random(7, 8, 9);
  int hits = 0, turnedAway = 0;
  for (int n = 0; n < 20000; ++n) {
    // From around the scene towards points near the moving things.
    Ray ray;
    ray.o = Vec3(random.next() * 12 - 6, random.next() * 6, random.next() * 12 - 6);
    const Vec3 target(random.next() * 7 - 3, random.next() * 2.5, random.next() * 3);
    ray.d = normalize(target - ray.o);
    ray.time = random.next();
    for (uint32_t e : {1u, 4u}) { // the sliding sphere and the turning CSG
      Hit hit;
      const bool hits_ = intersectShape(scene.entities[e], e, ray, hit);
      const bool away = boxes.misses(e, ray, ray.tMax);
      ASSERT_FALSE(hits_ && away) << "entity " << e << " at time " << ray.time;
      hits += hits_;
      turnedAway += away;
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(turnedAway, 1000);
}

std::string foldError(const char *body) {
  const std::string source = std::string(R"lua(
scene_info = SceneInfo() { image_width = 8, image_height = 8, shutter = 1 }
function scene(clock)
  local s = Scene()
)lua") + body + "\n  return s\nend\n";
  SceneScript script = SceneScript::fromString(source, "mismatch.lua");
  int calls = 0;
  try {
    buildFrameScene(script, script.info(), 0, calls);
  } catch (const SceneError &e) {
    return e.what();
  }
  return "";
}

TEST(MotionBlur, ScenesOfOneShutterThatDoNotMatchAreErrors) {
  EXPECT_EQ(foldError("if clock > 0 then s:add_entity(Sphere()) end"),
            "motion blur: scene(clock) at clock 0 and at clock 1 do not match: 0 entities, then "
            "1 (the scenes of one shutter are matched entity by entity and light by light, in "
            "the order they are added)");
  EXPECT_NE(foldError("s:add_entity(clock > 0 and Cube() or Sphere())")
                .find("entity 1 (Sphere, mismatch.lua:5) is a Cube there"),
            std::string::npos);
  EXPECT_NE(foldError("s:add_entity(Torus() { minor = 0.1 + 0.1 * clock })").find("radii"),
            std::string::npos);
  EXPECT_NE(foldError("s:add_entity(Mesh() { vertices = { {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, "
                      "{1, 1, 0} }, indices = clock > 0 and { {1, 3, 2} } or { {2, 3, 4} } })")
                .find("entity 1 (Mesh, mismatch.lua:5) changes its triangles"),
            std::string::npos);
  EXPECT_NE(foldError("if clock > 0 then s:add_light(Light()) end").find("0 lights, then 1"),
            std::string::npos);
  EXPECT_NE(foldError("s:add_entity(Difference { Sphere(), clock > 0 and Sphere() or Cube() })")
                .find("entity 1 (Difference, mismatch.lua:5) changes its parts: part 2 is a "
                      "Sphere there"),
            std::string::npos);
  // The same scene at every step, things moving: fine.
  EXPECT_EQ(foldError("s:add_entity(Sphere(Translate(Vector(clock, 0, 0))))"), "");
  EXPECT_EQ(foldError("s:add_entity(Mesh() { vertices = { {0, 0, 0}, {1, 0, 0}, "
                      "{0, 1 + clock, 0} }, indices = { {1, 3, 2} } })"),
            "");
}

} // namespace
} // namespace lray
