// SceneScript: the render loop's entry point (lua/README.md, "The scene file", "Scene and camera"),
// and every scene in scenes/ loading and building its first and last frames.
#include "bindings/scene_script.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include <unistd.h>
#include <fstream>

namespace lray {
namespace {

std::string errorOf(const std::function<void()> &f) {
  try {
    f();
  } catch (const SceneError &e) {
    return e.what();
  }
  return "";
}

constexpr const char *kMinimal = "function scene(clock) return Scene() end";

TEST(SceneScriptTest, DefaultsWithoutSceneInfo) {
  SceneScript script = SceneScript::fromString(kMinimal, "test.lua");
  EXPECT_EQ(script.info().imageWidth, 800);
  EXPECT_EQ(script.info().imageHeight, 600);
  EXPECT_EQ(script.info().frames, 1);
  EXPECT_EQ(script.info().samples, 1);
  EXPECT_EQ(script.info().startClock, 0);
  EXPECT_EQ(script.info().endClock, 1);
  Scene scene = script.buildFrame(0);
  EXPECT_TRUE(scene.entities.empty());
}

TEST(SceneScriptTest, SceneInfoAndTheClockReachTheScene) {
  SceneScript script = SceneScript::fromString(
      "scene_info = SceneInfo() { image_width = 320, image_height = 240, frames = 5,\n"
      "  samples = 2, start_clock = 1, end_clock = 3 }\n"
      "function scene(clock)\n"
      "  local s = Scene()\n"
      "  s:add_entity(Sphere(Translate(clock * x)))\n"
      "  return s\n"
      "end",
      "test.lua");
  const SceneInfo &info = script.info();
  EXPECT_EQ(info.imageWidth, 320);
  EXPECT_EQ(info.imageHeight, 240);
  EXPECT_EQ(info.frames, 5);
  EXPECT_EQ(info.samples, 2);
  EXPECT_EQ(info.clockForFrame(4), 3);
  Scene scene = script.buildFrame(info.clockForFrame(2));
  ASSERT_EQ(scene.entities.size(), 1u);
  EXPECT_EQ(scene.entities[0].worldFromObject.applyPoint({0, 0, 0}), Vec3(2, 0, 0));
  EXPECT_EQ(scene.entities[0].loc.str(), "test.lua:5");
  // The same script can build any frame, in any order.
  EXPECT_EQ(script.buildFrame(1).entities[0].worldFromObject.applyPoint({0, 0, 0}), Vec3(1, 0, 0));
}

TEST(SceneScriptTest, MaxPixelsCapsWidthTimesHeightTimesSamplesSquared) {
  ScriptOptions options;
  options.maxPixels = 1000;
  std::string source = "local a = 1\nscene_info = SceneInfo() { image_width = 20, image_height = "
                       "10, samples = 3 }\n";
  EXPECT_EQ(
      errorOf([&] { SceneScript::fromString(source + kMinimal, "test.lua", ".", options); }),
      "test.lua:2: SceneInfo: image_width * image_height * samples^2 = 1800 exceeds the limit "
      "of 1000 (raise it with --max-pixels)");
  options.maxPixels = 1800;
  EXPECT_EQ(errorOf([&] { SceneScript::fromString(source + kMinimal, "test.lua", ".", options); }),
            "");
}

TEST(SceneScriptTest, MaxLightSamplesCapsEachLightsShadowRaysPerPoint) {
  // A 100000 x 100000 area light would trace 1e10 shadow rays per hit.
  const std::string source = "function scene(clock)\n"
                             "  local s = Scene()\n"
                             "  s:add_light(Light() { rows = 100000, cols = 100000 })\n"
                             "  s:add_light(SpotLight())\n"
                             "  return s\n"
                             "end\n";
  ScriptOptions options;
  SceneScript script = SceneScript::fromString(source, "test.lua", ".", options);
  EXPECT_EQ(errorOf([&] { script.buildFrame(0); }),
            "test.lua:3: Light: 10000000000 shadow rays per shading point exceed the limit of "
            "65536 (raise it with --max-light-samples)");
  options.maxLightSamples = 20000000000;
  SceneScript raised = SceneScript::fromString(source, "test.lua", ".", options);
  EXPECT_NE(errorOf([&] { raised.buildFrame(0); }).find("exceed the limit of 2147483647"),
            std::string::npos);
  options.maxLightSamples = 1;
  SceneScript tiny = SceneScript::fromString("function scene(clock)\n"
                                             "  local s = Scene()\n"
                                             "  s:add_light(SpotLight())\n"
                                             "  return s\n"
                                             "end\n",
                                             "test.lua", ".", options);
  EXPECT_EQ(errorOf([&] { tiny.buildFrame(0); }), "");
}

TEST(SceneScriptTest, ScriptLevelErrors) {
  EXPECT_EQ(errorOf([] { SceneScript::fromString("local x = 1", "test.lua"); }),
            "test.lua: the script must define a global function scene(clock) returning a Scene");
  EXPECT_EQ(errorOf([] {
              SceneScript::fromString("scene_info = 3\n" + std::string(kMinimal), "test.lua");
            }),
            "test.lua: scene_info must be a SceneInfo, got number");
  EXPECT_EQ(errorOf([] { SceneScript::fromString("function scene(clock) end end", "test.lua"); }),
            "test.lua:1: <eof> expected near 'end'");
  SceneScript script = SceneScript::fromString("function scene(clock) return 42 end", "test.lua");
  EXPECT_EQ(errorOf([&] { script.buildFrame(0); }),
            "test.lua: scene(clock) must return a Scene, got number");
}

TEST(SceneScriptTest, ErrorsInsideSceneCarryMessageAndTraceback) {
  SceneScript script = SceneScript::fromString("function scene(clock)\n"
                                               "  local f = Finish()\n"
                                               "  f.diffuse = 'shiny'\n"
                                               "  return Scene()\n"
                                               "end",
                                               "test.lua");
  std::string error = errorOf([&] { script.buildFrame(0); });
  EXPECT_EQ(error.rfind("test.lua:3: Finish: attribute 'diffuse' expects a number, got string\n"
                        "stack traceback:",
                        0),
            0u)
      << error;
  EXPECT_NE(error.find("in function 'scene'"), std::string::npos) << error;
}

TEST(SceneScriptTest, TimeoutInsideScene) {
  ScriptOptions options;
  options.timeoutSeconds = 0.1;
  SceneScript script = SceneScript::fromString("function scene(clock)\n  while true do end\nend",
                                               "test.lua", ".", options);
  std::string error = errorOf([&] { script.buildFrame(0); });
  EXPECT_EQ(error.rfind("test.lua:2: the script ran longer than 0.1 seconds", 0), 0u) << error;
}

TEST(SceneScriptTest, AspectWarning) {
  SceneScript script = SceneScript::fromString(
      "scene_info = SceneInfo() { image_width = 400, image_height = 400 }\n" +
          std::string(kMinimal),
      "test.lua");
  script.buildFrame(0);
  ASSERT_EQ(script.warnings().size(), 1u);
  EXPECT_NE(script.warnings()[0].find("stretched"), std::string::npos);
}

TEST(SceneScriptTest, FilePathsResolveAgainstTheScriptFolder) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("lray_scene_script_test_" + std::to_string(getpid()));
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "sub" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "data.txt") << "7\n";
  std::ofstream(dir / "scene.lua")
      << "local n = tonumber(io.lines('data.txt')())\n"
         "local m = mesh_from_obj('sub/tri.obj')\n"
         "function scene(clock)\n"
         "  local s = Scene(); s:add_entity(m:copy() { transform = Translate(n * x) })\n"
         "  return s\n"
         "end\n";
  SceneScript script((dir / "scene.lua").string());
  Scene scene = script.buildFrame(0);
  ASSERT_EQ(scene.entities.size(), 1u);
  EXPECT_EQ(scene.entities[0].worldFromObject.applyPoint({0, 0, 0}), Vec3(7, 0, 0));
  EXPECT_EQ(scene.entities[0].mesh->triangles.size(), 1u);
  EXPECT_EQ(scene.entities[0].loc.str(), (dir / "scene.lua").string() + ":4");

  std::ofstream(dir / "bad.lua") << "\n\nlocal m = mesh_from_obj('nothing.obj')\n";
  EXPECT_EQ(errorOf([&] { SceneScript((dir / "bad.lua").string()); })
                .rfind((dir / "bad.lua").string() +
                           ":3: mesh_from_obj: nothing.obj: cannot open OBJ file",
                       0),
            0u);
  EXPECT_EQ(errorOf([&] { SceneScript((dir / "missing.lua").string()); }),
            (dir / "missing.lua").string() + ": cannot open the scene file");
  fs::remove_all(dir);
}

TEST(SceneScriptTest, MoveKeepsTheState) {
  SceneScript a = SceneScript::fromString(
      "scene_info = SceneInfo() { frames = 3 }\n" + std::string(kMinimal), "a.lua");
  SceneScript b = std::move(a);
  EXPECT_EQ(b.info().frames, 3);
  EXPECT_NO_THROW(b.buildFrame(0));
}

// ---- every example scene ----------------------------------------------------------

std::vector<std::string> exampleScenes() {
  std::vector<std::string> names;
  for (const auto &entry : std::filesystem::directory_iterator(LRAY_SOURCE_DIR "/scenes"))
    if (entry.path().extension() == ".lua") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class ExampleSceneTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleSceneTest, LoadsAndBuildsFirstAndLastFrames) {
  SceneScript script(std::string(LRAY_SOURCE_DIR "/scenes/") + GetParam());
  const SceneInfo &info = script.info();
  for (int frame : {0, info.frames - 1}) {
    Scene scene = script.buildFrame(info.clockForFrame(frame));
    EXPECT_FALSE(scene.entities.empty());
    // Lit by a light, or by an emitting object (the path tracer's scenes).
    const bool emits = std::any_of(scene.textures.begin(), scene.textures.end(),
                                   [](const Texture &t) { return !t.finish.emission.isBlack(); });
    EXPECT_TRUE(!scene.lights.empty() || emits);
    EXPECT_FALSE(scene.textures.empty());
    EXPECT_TRUE(script.warnings().empty()) << script.warnings()[0];
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, ExampleSceneTest, ::testing::ValuesIn(exampleScenes()),
                         [](const auto &param) {
                           std::string name = param.param.substr(0, param.param.find('.'));
                           return name;
                         });

TEST(ExampleScenesTest, RingIsListingOne) {
  SceneScript script(LRAY_SOURCE_DIR "/scenes/ring.lua");
  EXPECT_EQ(script.info().frames, 20);
  Scene scene = script.buildFrame(0);
  EXPECT_EQ(scene.entities.size(), 20u);
  EXPECT_EQ(scene.camera.worldFromCamera.applyPoint({0, 0, 0}), Vec3(0, 0, -5));
  Scene half = script.buildFrame(0.5);
  Vec3 eye = half.camera.worldFromCamera.applyPoint({0, 0, 0});
  EXPECT_NEAR(eye.x, 0, 1e-9);
  EXPECT_NEAR(eye.z, 5, 1e-9);
}

} // namespace
} // namespace lray
