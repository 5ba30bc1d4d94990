// The comparator on real path-traced renders (lray's Film, with the
// variance its EXR carries): the same scene at another seed passes at the
// stated false-alarm rate; one light 1 % brighter, the texture shifted by
// one texel, one small object missing, and a NaN pixel each fail.
#include "compare/compare_image.h"
#include "compare/comparison.h"

#include "bindings/scene_script.h"
#include "render/film.h"
#include "run/frame_pipeline.h"
#include "shading/image_cache.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace lray;
using namespace lray::compare;
namespace fs = std::filesystem;

namespace {

struct Variant {
  double light = 1; ///< the second light's strength
  int shift = 0;    ///< texels the texture is rolled by
  bool ball = true; ///< the small sphere
  int samples = 8;  ///< samples = n: n x n per pixel
};

/// An 8 x 8 texture of random-looking greys, rolled `shift` texels in s.
std::string writeTexture(const fs::path &dir, int shift) {
  std::vector<unsigned char> rgb;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const int sx = ((x - shift) % 8 + 8) % 8;
      const auto v = static_cast<unsigned char>(40 + (sx * 97 + y * 57) % 180);
      rgb.insert(rgb.end(), {v, v, v});
    }
  const fs::path path = dir / fmt::format("texture{}.png", shift);
  writePng(path.string(), 8, 8, rgb);
  return path.filename().string();
}

CompareImage render(const Variant &v, uint32_t seed) {
  // Per process: two test runs at once (a CI clone beside a checkout) must
  // not write each other's scene.
  const fs::path dir =
      fs::temp_directory_path() / ("lray_render_compare_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string texture = writeTexture(dir, v.shift);
  const std::string source = fmt::format(R"lua(
scene_info = SceneInfo() {{ image_width = 48, image_height = 36, samples = {},
                           integrator = "path", max_depth = 3 }}
local matte = Finish() {{ ambient = grey(0), diffuse = 1, specular = 0 }}
function scene(clock)
  local s = Scene() {{ background_color = Color(0.1, 0.1, 0.1),
    camera = Perspective(50, 48 / 36) {{
      transform = LookAt(Vector(0, 1.2, -3), Vector(0, 0.5, 0), y) }} }}
  s:add_entity(Mesh() {{ vertices = {{ {{-2, 0, -2}}, {{2, 0, -2}}, {{2, 0, 2}}, {{-2, 0, 2}} }},
    uvs = {{ {{0, 0}}, {{1, 0}}, {{1, 1}}, {{0, 1}} }},
    indices = {{ {{ {{1, 1}}, {{3, 3}}, {{2, 2}} }}, {{ {{1, 1}}, {{4, 4}}, {{3, 3}} }} }},
    texture = Texture() {{ pigment = ImagePigment2D("{}"),
                          finish = matte }} }})
  if {} then
    s:add_entity(Sphere(Translate(Vector(0.3, 0.25, 0)) * Scale(0.25)) {{
      texture = Texture() {{ pigment = ColorPigment(Color(0.9, 0.2, 0.1)),
                            finish = matte }} }})
  end
  s:add_light(Light() {{ color = grey(0.6), rows = 2, cols = 2, area = true,
                        transform = Translate(Vector(-2, 4, -2)) }})
  s:add_light(Light() {{ color = grey(0.5 * {}), transform = Translate(Vector(3, 5, -1)) }})
  return s
end
)lua",
                                         v.samples, texture, v.ball ? "true" : "false", v.light);
  const fs::path scene = dir / "scene.lua";
  std::ofstream(scene) << source;
  ScriptOptions options;
  SceneScript script(scene.string(), options);
  const SceneInfo info = script.info();
  FrameSettings settings;
  settings.integrator = IntegratorKind::Path;
  settings.maxDepth = 3;
  settings.seed = seed;
  ImageCache images(false);
  FrameStats stats;
  const Film film = renderScriptFrame(script, info, 0, "embree", images, stats, nullptr, settings);
  CompareImage im;
  im.width = film.width();
  im.height = film.height();
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const Color c = film.get(x, y), var = film.variance(x, y);
      im.rgb.insert(im.rgb.end(), {float(c.r), float(c.g), float(c.b)});
      im.variance.insert(im.variance.end(), {float(var.r), float(var.g), float(var.b)});
      im.samples.push_back(static_cast<float>(film.sampleCount(x, y)));
    }
  fs::remove_all(dir);
  return im;
}

Criteria noise(double alpha) { return {.metric = Metric::Noise, .threshold = alpha}; }

} // namespace

TEST(RenderCompare, TheSameSceneAtAnotherSeedPassesAtTheStatedRate) {
  // 40 independent pairs at alpha 0.1: 4 expected at most; 11 is beyond 3
  // binomial standard deviations. (Stratified samples vary less than their
  // sample variance says, so the true rate is lower.)
  int failures = 0;
  for (uint32_t i = 0; i < 40; ++i)
    failures += !compareImages(render({1, 0, true, 4}, 100 + 2 * i),
                               render({1, 0, true, 4}, 101 + 2 * i), noise(0.1))
                     .pass;
  EXPECT_LE(failures, 11);
}

TEST(RenderCompare, OneLightOnePercentBrighterFails) {
  const Outcome o = compareImages(render({1.01}, 1), render({}, 2), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
}

TEST(RenderCompare, TheTextureShiftedByOneTexelFails) {
  const Outcome o = compareImages(render({1, 1}, 1), render({}, 2), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
}

TEST(RenderCompare, OneSmallObjectMissingFails) {
  const Outcome o = compareImages(render({1, 0, false}, 1), render({}, 2), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
}

TEST(RenderCompare, ANanPixelFails) {
  CompareImage a = render({}, 1);
  a.rgb[(10 * 48 + 10) * 3] = std::nanf("");
  const Outcome o = compareImages(a, render({}, 2), noise(0.01));
  EXPECT_FALSE(o.pass) << o.verdict;
  EXPECT_EQ(o.nonFinite, 1u);
}

TEST(RenderCompare, FilmVarianceIsNothingWhereSamplesAgreeAndSomethingWhereTheyDiffer) {
  // In both sampling modes: about 0 where the samples agree (the
  // background), positive on the silhouette and in the penumbra.
  const fs::path dir =
      fs::temp_directory_path() / ("lray_film_variance_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "scene.lua") << R"lua(
scene_info = SceneInfo() { image_width = 24, image_height = 16, samples = 4 }
function scene(clock)
  local s = Scene() { background_color = Color(0.2, 0.3, 0.4),
    camera = Perspective(40, 1.5) { transform = LookAt(Vector(0, 0, -4), Vector(0, 0, 0), y) } }
  s:add_entity(Sphere(Scale(0.8)) { texture = Texture() { finish = Finish() { diffuse = 0.9 } } })
  s:add_light(Light() { rows = 4, cols = 4, area = true, transform = Translate(Vector(-3, 5, -4)) })
  return s
end
)lua";
  ScriptOptions options;
  SceneScript script((dir / "scene.lua").string(), options);
  const SceneInfo info = script.info();
  ImageCache images(false);
  FrameStats stats;
  FrameSettings fixed;
  fixed.lightSampling = LightSampling::Spread;
  const Film a = renderScriptFrame(script, info, 0, "embree", images, stats, nullptr, fixed);
  FrameSettings adaptive = fixed;
  adaptive.adaptive = true;
  adaptive.adaptiveSettings.noiseThreshold = 0; // every pixel takes every sample
  adaptive.adaptiveSettings.minSamples = 4;
  adaptive.adaptiveSettings.maxSamples = 16;
  const Film b = renderScriptFrame(script, info, 0, "embree", images, stats, nullptr, adaptive);
  EXPECT_LT(a.variance(0, 0).r, 1e-12); // background
  EXPECT_LT(b.variance(0, 0).r, 1e-12);
  int edge = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      ASSERT_EQ(a.sampleCount(x, y), 16u);
      ASSERT_EQ(b.sampleCount(x, y), 16u);
      const double va = a.variance(x, y).g, vb = b.variance(x, y).g;
      EXPECT_GE(va, 0);
      EXPECT_GE(vb, 0);
      edge += va > 1e-4 && vb > 1e-4;
    }
  EXPECT_GT(edge, 10);
  fs::remove_all(dir);
}
