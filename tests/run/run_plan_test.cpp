// Tests for src/run/run_plan: the one description of a run's settings
// (README.md, "Command line"). Every option of lray is either a render
// setting, checked here against the fingerprint that keeps tiles of
// different renders apart, or listed with the reason it cannot change a
// pixel; a new option fails OptionsAreEachClassified until it is one of them.
#include "app/cli_fixture.h"
#include "run/options.h"
#include "run/run_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace lray {
namespace {

using namespace cli_test;

/// A render setting: the same scene rendered with `base` and with `changed`.
struct SettingPair {
  const char *option;
  const char *base;
  const char *changed;
};

const SettingPair kRenderSettings[] = {
    {"--backend", "", "--backend kdtree"},
    {"--threads", "-t 2", "-t 1"},
    {"--width", "", "-w 20"},
    {"--height", "", "-H 10"},
    {"--samples", "", "-s 2"},
    {"--noise-threshold", "", "--noise-threshold 0.05 --max-samples 8"},
    {"--min-samples", "--noise-threshold 0.05 --max-samples 8",
     "--noise-threshold 0.05 --max-samples 8 --min-samples 2"},
    {"--edge-lattice", "--noise-threshold 0.05 --min-samples 1",
     "--noise-threshold 0.05 --min-samples 1 --edge-lattice 2"},
    {"--sparse-centres", "--noise-threshold 0.5 --min-samples 1",
     "--noise-threshold 0.5 --min-samples 1 --sparse-centres"},
    {"--max-samples", "--noise-threshold 0.001 --max-samples 8",
     "--noise-threshold 0.001 --max-samples 4"},
    {"--time-limit", "--noise-threshold 0.001 --max-samples 4",
     "--noise-threshold 0.001 --max-samples 4 --time-limit 1000"},
    {"--seed", "-s 2", "-s 2 --seed 7"},
    {"--light-sampling", "-s 2", "-s 2 --light-sampling spread"},
    {"--integrator", "", "--integrator path"},
    {"--max-depth", "--integrator path", "--integrator path --max-depth 1"},
    {"--clamp", "--integrator path", "--integrator path --clamp 0.05"},
    {"--shutter", "", "--shutter 0.5"},
    {"--motion-steps", "--shutter 0.5", "--shutter 0.5 --motion-steps 5"},
    {"--linear", "", "--linear"},
    {"--aovs", "-f exr", "-f exr --aovs"},
    {"--no-shadow-skips", "", "--no-shadow-skips"},
};

/// Options that cannot change a pixel of a frame, and why.
const std::set<std::string> kNotRenderSettings = {
    "--help", "--version",              // print and exit
    "--info", "--tiles",                // describe the run, render nothing
    "--frames", "--skip-existing",      // which frames, not their pixels
    "--tile", "--crop",                 // which pixels: the tile's header records its window
    "--format",                         // the file, not the pixels: the header records it
    "--quiet", "--stats",               // what is printed
    "--unsafe", "--script-timeout", "--allow-read", "--max-file-size", "--script-memory",
    "--render-memory", "--max-light-samples", "--max-pixels", // limits: no pixel changes
    "--watch", "--serve",               // the live preview, which writes no tiles
};

// Two spheres under an area light over a checkered floor: every sampling
// choice shows in some pixel. One moves along a curve (motion blur).
const char *kScene = R"(
scene_info = SceneInfo() { image_width = 16, image_height = 12, samples = 1 }
function scene(clock)
  local s = Scene() { camera = Perspective(45, 16/12) { transform = Translate(-6*z) } }
  s:add_entity(Sphere(Translate(Vector(-0.6 + clock * clock, 0, 0)) * Scale(0.7, 0.7, 0.7)))
  s:add_entity(Sphere(Translate(Vector(0.8, 0.2, 1))) {
    texture = Texture() { pigment = CheckerPigment3D() {
      pigment1 = ColorPigment(Color(1, 0, 0)), pigment2 = ColorPigment(Color(0, 0, 1)) } } })
  s:add_light(Light() { transform = Translate(Vector(-3, 3, -3)), rows = 3, cols = 3,
                         area = true })
  return s
end
)";

class RunPlanTest : public LrayCli {
protected:
  /// The bytes of the image `args` renders, and the fingerprint --info gives.
  std::pair<std::string, std::string> render(const std::string &args, const std::string &name) {
    const fs::path scene = dir_ / "plan.lua";
    if (!fs::exists(scene)) writeScene("plan.lua", kScene);
    std::string folder = name;
    std::replace(folder.begin(), folder.end(), ' ', '_');
    const fs::path out = dir_ / folder;
    Result r = runLray(scene.string() + " " + out.string() + " --quiet " + args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.output;
    Result info = runLray(scene.string() + " --info " + args);
    EXPECT_EQ(info.status, 0) << args << ": " << info.output;
    const std::string key = "\"fingerprint\":\"";
    const size_t at = info.output.find(key);
    EXPECT_NE(at, std::string::npos) << info.output;
    std::string fingerprint =
        at == std::string::npos ? "" : info.output.substr(at + key.size(), 16);
    std::string image;
    for (const auto &entry : fs::directory_iterator(out)) image = readFile(entry.path());
    return {image, fingerprint};
  }
};

TEST(RunPlan, OptionsAreEachClassified) {
  std::set<std::string> settings;
  for (const SettingPair &p : kRenderSettings) settings.insert(p.option);
  for (const std::string &name : optionNames()) {
    const bool render = settings.count(name) > 0, other = kNotRenderSettings.count(name) > 0;
    EXPECT_TRUE(render != other)
        << name << ": add it to kRenderSettings (with two values to render) or, if it cannot "
        << "change a pixel, to kNotRenderSettings";
  }
  EXPECT_GT(optionNames().size(), 30u);
}

TEST_F(RunPlanTest, EverySettingThatChangesPixelsChangesTheFingerprint) {
  int changed = 0;
  for (const SettingPair &p : kRenderSettings) {
    SCOPED_TRACE(p.option);
    const auto [baseImage, baseFingerprint] = render(p.base, std::string("base") + p.option);
    const auto [image, fingerprint] = render(p.changed, std::string("changed") + p.option);
    ASSERT_FALSE(baseImage.empty());
    if (image != baseImage) {
      ++changed;
      EXPECT_NE(fingerprint, baseFingerprint)
          << "'" << p.changed << "' changes pixels but not the fingerprint: describe it in "
          << "RunPlan::settings() as a setting that changes pixels";
    }
  }
  // Most of them do change this scene's pixels (else the test checks nothing).
  EXPECT_GE(changed, 9);
}

TEST_F(RunPlanTest, SettingsThatCannotChangePixelsLeaveThemAlone) {
  // The plan's settings that claim not to change pixels (shadow skips,
  // threads) leave every byte of the image as it was.
  for (const char *args : {"--no-shadow-skips", "-t 1"}) {
    SCOPED_TRACE(args);
    EXPECT_EQ(render(args, std::string("changed") + args).first, render("-t 2", "base").first);
  }
}

TEST_F(RunPlanTest, InfoListsEachPlannedFrameAndItsTiles) {
  const fs::path scene = writeScene("anim.lua", R"(
scene_info = SceneInfo() { image_width = 20, image_height = 40, frames = 12 }
function scene(clock) return Scene() end
)");
  Result r = runLray(scene.string() + " out --info --frames 9:11:2 --tiles 3 -f exr");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(R"("outputs":[{"frame":9,"clock":)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(R"("file":"anim0009.exr","tiles":["anim0009.tile-0-of-3.exr",)"
                          R"("anim0009.tile-1-of-3.exr","anim0009.tile-2-of-3.exr"]})"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(R"("file":"anim0011.exr")"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("anim0010"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(R"("settings":{"backend":"embree")"), std::string::npos) << r.output;
  // 40 rows of pixels are 3 rows of 16-pixel tiles: 4 tiles would leave one empty.
  Result tooMany = runLray(scene.string() + " --info --tiles 4");
  EXPECT_EQ(tooMany.status, 1);
  EXPECT_NE(tooMany.output.find("at most 3 tiles"), std::string::npos) << tooMany.output;
  Result alone = runLray(scene.string() + " out --tiles 2");
  EXPECT_EQ(alone.status, 2) << alone.output;
}

TEST_F(RunPlanTest, StatsCarryThePlansSettings) {
  writeScene("plan.lua", kScene);
  const fs::path stats = dir_ / "stats.json";
  Result r = runLray((dir_ / "plan.lua").string() + " " + (dir_ / "o").string() +
                     " --quiet --seed 5 --stats " + stats.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string json = readFile(stats);
  EXPECT_NE(json.find(R"("settings": {"backend":"embree","integrator":"whitted","max_depth":8,)"
                      R"("clamp":0,"width":16,)"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(R"("seed":5,)"), std::string::npos) << json;
  // Off is off: a setting's JSON is its value, whether it counts or not.
  EXPECT_NE(json.find(R"("edge_lattice":0,"sparse_centres":false,)"), std::string::npos) << json;
}

} // namespace
} // namespace lray
