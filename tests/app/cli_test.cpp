// End-to-end tests of the lray binary (README.md, "The `lray` command"): exit codes, messages, file
// names, frame ranges, --stats, and byte-identical output across thread counts.
#include "cli_fixture.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace lray {
namespace {

using namespace cli_test;
namespace fs = std::filesystem;

// A small lit scene with shadows and area-light jitter, so thread-count
// independence covers the random streams too.
const char *kSpheres = R"(
scene_info = SceneInfo() { image_width = 48, image_height = 36, frames = 3, samples = 2 }
function scene(clock)
  local s = Scene() { camera = Perspective(45, 48/36) { transform = Translate(-6*z) } }
  for i = 1, 5 do
    s:add_entity(Sphere(Translate(Vector(i - 3, 0.3*clock, 0)) * Scale(0.4, 0.4, 0.4)))
  end
  s:add_light(Light() { transform = Translate(Vector(-3, 3, -3)), rows = 2, cols = 2, area = true })
  return s
end
)";

TEST_F(LrayCli, MissingSceneFileIsOneClearLine) {
  Result r = runLray((dir_ / "nope.lua").string() + " " + (dir_ / "out").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("nope.lua"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

TEST_F(LrayCli, BadOptionIsAUsageError) {
  fs::path scene = writeScene("s.lua", kSpheres);
  Result r = runLray(scene.string() + " " + (dir_ / "out").string() + " --bogus");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  Result b = runLray(scene.string() + " " + (dir_ / "out").string() + " --backend optix");
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.output.find("optix"), std::string::npos) << b.output;
}

TEST_F(LrayCli, UnwritableOutDirIsAnError) {
  fs::path scene = writeScene("s.lua", kSpheres);
  writeScene("a_file", "x");
  Result r = runLray(scene.string() + " " + (dir_ / "a_file" / "out").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("cannot create output folder"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

TEST_F(LrayCli, HelpAndVersion) {
  Result h = runLray("--help");
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.output.find("--frames"), std::string::npos);
  Result v = runLray("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_EQ(v.output.rfind("lray ", 0), 0u) << v.output;
}

TEST_F(LrayCli, AnimationFileNamesAndFrameRange) {
  fs::path scene = writeScene("anim.lua", kSpheres);
  fs::path out = dir_ / "out";
  Result r = runLray(scene.string() + " " + out.string() + " --quiet --frames 1:2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "anim0000.png"));
  EXPECT_TRUE(fs::exists(out / "anim0001.png"));
  EXPECT_TRUE(fs::exists(out / "anim0002.png"));
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 2);
  Result bad = runLray(scene.string() + " " + out.string() + " --quiet --frames 2:3");
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.output.find("3 frames"), std::string::npos) << bad.output;
}

TEST_F(LrayCli, AnAnimationsFramesAreTheSameBytesWrittenBesideTheRenderOrAfterIt) {
  // One thread writes each frame before the next renders; more write them
  // while the next ones render (app/frame_writer.h).
  fs::path scene = writeScene("aw.lua", kSpheres);
  for (const char *format : {"png", "tga", "exr"}) {
    for (int threads : {1, 2, 6}) {
      const fs::path out = dir_ / (std::string(format) + std::to_string(threads));
      Result r = runLray(scene.string() + " " + out.string() + " --quiet --format " + format +
                         " --threads " + std::to_string(threads));
      ASSERT_EQ(r.status, 0) << r.output;
      for (int frame = 0; frame < 3; ++frame) {
        const std::string name = "aw000" + std::to_string(frame) + "." + format;
        const std::string bytes = readFile(out / name);
        ASSERT_FALSE(bytes.empty()) << name;
        EXPECT_EQ(bytes, readFile(dir_ / (std::string(format) + "1") / name))
            << name << " with " << threads << " threads";
      }
      EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 3);
    }
  }
}

TEST_F(LrayCli, AFailedFrameWriteStopsTheRunNamingTheFileAndLeavesNoTemporaryFile) {
  fs::path scene = writeScene("wf.lua", kSpheres);
  for (int threads : {1, 2, 6}) {
    const fs::path out = dir_ / ("o" + std::to_string(threads));
    fs::create_directories(out / "wf0001.png" / "inside"); // frame 1's name is taken
    Result r = runLray(scene.string() + " " + out.string() + " --quiet --threads " +
                       std::to_string(threads));
    EXPECT_EQ(r.status, 1) << threads;
    EXPECT_NE(r.output.find("cannot write image '" + (out / "wf0001.png").string() +
                            "': a folder of that name is in the way"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(readFile(out / "wf0000.png").empty()) << threads; // the frame before is whole
    for (const auto &entry : fs::directory_iterator(out))
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
          << entry.path();
  }
}

TEST_F(LrayCli, OneFrameSceneIsNamedAfterTheScript) {
  fs::path scene = writeScene("still.lua", "function scene(clock) return Scene() end\n");
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() +
                     " --quiet --width 8 --height 6 --format tga");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "o" / "still.tga"));
}

TEST_F(LrayCli, SameBytesWhateverTheThreadCountOnBothBackends) {
  // 1, 2 and many (more threads than tiles in a row, more than cores)
  // threads; with the path tracer too (its samples' random numbers are
  // keyed by pixel and sample, like the camera's).
  fs::path scene = writeScene("det.lua", kSpheres);
  for (const char *integrator : {"whitted", "path"}) {
    std::string first;
    for (const char *backend : {"embree", "kdtree"}) {
      for (int threads : {1, 2, 8}) {
        const fs::path out = dir_ / (std::string(integrator) + backend + std::to_string(threads));
        Result r = runLray(scene.string() + " " + out.string() + " --quiet --frames 1 --backend " +
                           backend + " --threads " + std::to_string(threads) + " --integrator " +
                           integrator);
        ASSERT_EQ(r.status, 0) << r.output;
        std::string bytes = readFile(out / "det0001.png");
        ASSERT_FALSE(bytes.empty());
        if (first.empty()) first = bytes;
        EXPECT_EQ(bytes, first) << integrator << " on " << backend << " with " << threads
                                << " threads";
      }
    }
    if (std::string(integrator) == "path") { // and the path tracer's picture is its own
      EXPECT_NE(first, readFile(dir_ / "whittedembree1" / "det0001.png"));
    }
  }
  // And the picture is not trivially uniform: it differs from an empty scene's.
  fs::path blank = writeScene("blank.lua", "scene_info = SceneInfo() { image_width = 48, "
                                           "image_height = 36 }\nfunction scene(c) return "
                                           "Scene() end\n");
  ASSERT_EQ(runLray(blank.string() + " " + (dir_ / "b").string() + " --quiet").status, 0);
  EXPECT_NE(readFile(dir_ / "b" / "blank.png"),
            readFile(dir_ / "whittedembree1" / "det0001.png"));
}

TEST_F(LrayCli, CsgWithCoincidentFacesIsTheSameBytesOnBothBackendsAndAnyThreadCount) {
  // A red cube minus a green box sharing its front face, turned: the carved
  // (green) wall shows, never speckles of the shared red face.
  fs::path scene =
      writeScene("csg.lua", "scene_info = SceneInfo() { image_width = 40, image_height = 30 }\n"
                            "function scene()\n"
                            "  local s = Scene() { camera = Perspective(40, 4 / 3) { transform = "
                            "LookAt(Vector(0.7, 0.9, -3), origin, y) } }\n"
                            "  s:add_entity(Difference {\n"
                            "    Cube() { texture = Texture() { pigment = ColorPigment(red) } },\n"
                            "    Cube(Translate(Vector(0, 0, -0.3)) * Scale(0.6, 0.6, 0.4)) { "
                            "texture = Texture() { pigment = ColorPigment(green) } },\n"
                            "    transform = Rotate(Vector(1, 2, 3), 17) * Scale(1.3),\n"
                            "  })\n"
                            "  s:add_light(Light() { transform = Translate(Vector(-2, 3, -4)) })\n"
                            "  return s\nend\n");
  std::string first;
  for (const char *backend : {"embree", "kdtree"}) {
    for (int threads : {1, 2, 8}) {
      fs::path out = dir_ / ("c" + std::string(backend) + std::to_string(threads));
      Result r = runLray(scene.string() + " " + out.string() + " --quiet --backend " + backend +
                         " --threads " + std::to_string(threads));
      ASSERT_EQ(r.status, 0) << r.output;
      std::string bytes = readFile(out / "csg.png");
      ASSERT_FALSE(bytes.empty());
      if (first.empty()) first = bytes;
      EXPECT_EQ(bytes, first) << backend << " with " << threads << " threads";
    }
  }
}

TEST_F(LrayCli, StatsJsonCountsRays) {
  fs::path scene = writeScene("st.lua", kSpheres);
  fs::path stats = dir_ / "stats.json";
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() + " --quiet --frames 0 --stats " +
                     stats.string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::string json = readFile(stats);
  // 48 x 36 pixels x 2 x 2 samples.
  EXPECT_NE(json.find("\"camera\": 6912"), std::string::npos) << json;
  EXPECT_NE(json.find("\"backend\": \"embree\""), std::string::npos);
  EXPECT_NE(json.find("\"non_finite_samples\": 0"), std::string::npos);
  EXPECT_NE(json.find("\"build\""), std::string::npos);
}

TEST_F(LrayCli, AdaptiveSamplingReportsItsPassesSamplesAndError) {
  fs::path scene = writeScene("ad.lua", kSpheres);
  fs::path stats = dir_ / "stats.json";
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() +
                     " --quiet --frames 1 --noise-threshold 0.05 --min-samples 4 --max-samples 64 "
                     "--stats " + stats.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "o" / "ad0001.png"));
  std::string json = readFile(stats);
  EXPECT_NE(json.find(R"("mode": "adaptive", "light_sampling": "spread", "noise_threshold": 0.05, )"
                      R"("min_samples": 4, "max_samples": 64)"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"passes\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"max_pixel_samples\": 64"), std::string::npos) << json;
  EXPECT_NE(json.find("\"time_limit_hit\": false"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"error\": {\"mean\": null"), std::string::npos) << json;
}

TEST_F(LrayCli, SceneInfoNoiseThresholdTurnsOnAdaptiveSampling) {
  std::string text = kSpheres;
  text.replace(text.find("samples = 2"), 11, "noise_threshold = 0.1");
  fs::path scene = writeScene("nt.lua", text);
  fs::path stats = dir_ / "stats.json";
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() + " --quiet --frames 0 --stats " +
                     stats.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(readFile(stats).find("\"mode\": \"adaptive\""), std::string::npos);
}

TEST_F(LrayCli, SamplingOptionsThatContradictEachOtherAreRefused) {
  fs::path scene = writeScene("c.lua", kSpheres);
  const std::string base = scene.string() + " " + (dir_ / "o").string() + " --quiet ";
  Result r = runLray(base + "--samples 2 --noise-threshold 0.01");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--samples sets fixed n x n sampling"), std::string::npos) << r.output;
  r = runLray(base + "--max-samples 8");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("apply to adaptive sampling"), std::string::npos) << r.output;
  r = runLray(base + "--noise-threshold 0.01 --min-samples 64 --max-samples 8");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--min-samples (64) is above --max-samples (8)"), std::string::npos)
      << r.output;
  r = runLray(base + "--light-sampling some");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--light-sampling: unknown value 'some' (expected all or spread"),
            std::string::npos)
      << r.output;
  r = runLray(base + "--aovs");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--aovs needs EXR output"), std::string::npos) << r.output;
  r = runLray(base + "--noise-threshold -1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("expects a number >= 0, got '-1'"), std::string::npos) << r.output;
  r = runLray(base + "--noise-threshold 0.01 --max-samples 1000000000 -w 100 -H 100");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("max samples = 10000000000000 exceeds the limit"), std::string::npos)
      << r.output;
  // The edge lattice's contradictions: exit 1 (a scene setting) or 2 (usage).
  auto refused = [&](const std::string &args, int status, const std::string &message) {
    const Result result = runLray(base + args);
    EXPECT_EQ(result.status, status) << args;
    EXPECT_NE(result.output.find(message), std::string::npos) << args << ": " << result.output;
  };
  refused("--edge-lattice 3", 1, "--edge-lattice refines by the noise threshold");
  refused("--noise-threshold 0.1 --min-samples 4 --edge-lattice 3", 1,
          "it takes --min-samples 1, not 4");
  refused("--noise-threshold 0.1 --integrator path --edge-lattice 3", 1,
          "--edge-lattice applies to the Whitted integrator");
  refused("--noise-threshold 0.1 --edge-lattice 5 -w 10000 -H 10000", 1,
          "lattice points a pixel = 108900000000 exceeds the limit");
  refused("--noise-threshold 0.1 --edge-lattice 6", 2, "--edge-lattice");
  // And the sparse centres'.
  refused("--sparse-centres", 1, "--sparse-centres fills by the noise threshold");
  refused("--noise-threshold 0.1 --min-samples 4 --sparse-centres", 1,
          "--sparse-centres is a centre-first pass: it takes --min-samples 1, not 4");
  refused("--noise-threshold 0.1 --integrator path --sparse-centres", 1,
          "--sparse-centres applies to the Whitted integrator");
  EXPECT_FALSE(fs::exists(dir_ / "o" / "c0000.png"));
}

TEST_F(LrayCli, TimeLimitWritesTheImageItReached) {
  fs::path scene = writeScene("tl.lua", kSpheres);
  fs::path stats = dir_ / "stats.json";
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() +
                     " --quiet --frames 0 --time-limit 0.3 --max-samples 200000 --stats " +
                     stats.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "o" / "tl0000.png"));
  EXPECT_NE(readFile(stats).find("\"time_limit_hit\": true"), std::string::npos);
}

TEST_F(LrayCli, SeedGivesAnotherIndependentStreamAndZeroIsTheDefault) {
  fs::path scene = writeScene("sd.lua", kSpheres);
  auto render = [&](const std::string &dir, const std::string &args) {
    Result r =
        runLray(scene.string() + " " + (dir_ / dir).string() + " --quiet --frames 1 " + args);
    EXPECT_EQ(r.status, 0) << r.output;
    return readFile(dir_ / dir / "sd0001.png");
  };
  const std::string plain = render("a", ""), zero = render("b", "--seed 0"),
                    one = render("c", "--seed 1"), again = render("d", "--seed 1");
  EXPECT_EQ(plain, zero);
  EXPECT_EQ(one, again);
  EXPECT_NE(plain, one);
}

TEST_F(LrayCli, StatsOverADirectoryIsAnErrorThatLeavesNoTemporaryFile) {
  fs::path scene = writeScene("st.lua", kSpheres);
  fs::path stats = dir_ / "stats.json";
  fs::create_directories(stats / "inside"); // a non-empty folder under the stats name
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() + " --quiet --frames 0 --stats " +
                     stats.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("cannot write statistics '" + stats.string() +
                          "': a folder of that name is in the way"),
            std::string::npos)
      << r.output;
  for (const auto &entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find("stats.json.tmp"), std::string::npos)
        << entry.path();
}

TEST_F(LrayCli, ScriptErrorNamesFileAndLineAndWritesNothing) {
  fs::path scene = writeScene("broken.lua", "function scene(clock)\n  local s = Scene()\n  "
                                            "s:add_entity(nil_value.x)\n  return s\nend\n");
  fs::path out = dir_ / "o";
  Result r = runLray(scene.string() + " " + out.string() + " --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("broken.lua:3"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "broken.png"));
}

TEST_F(LrayCli, AbsurdImageSizeIsRefused) {
  fs::path scene = writeScene("big.lua", "scene_info = SceneInfo() { image_width = 100000, "
                                         "image_height = 100000 }\nfunction scene(c) return "
                                         "Scene() end\n");
  Result r = runLray(scene.string() + " " + (dir_ / "o").string() + " --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("--max-pixels"), std::string::npos) << r.output;
}

TEST_F(LrayCli, RelativeScenePathFromAnotherFolder) {
  fs::create_directories(dir_ / "sub");
  writeScene("sub/rel.lua", "function scene(c) return Scene() end\n");
  std::string cmd = "cd " + dir_.string() + " && " + std::string(LRAY_BINARY) +
                    " sub/rel.lua out --quiet -w 4 -H 4 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_TRUE(fs::exists(dir_ / "out" / "rel.png"));
}

} // namespace
} // namespace lray
