// The render-farm flags end to end (issue 21): --frames A:B:STEP,
// --skip-existing, --tile I/N and --crop with lray-merge. A frame stitched
// from tiles is byte-identical to the frame rendered whole, on both
// backends, for fixed and adaptive sampling, PNG and EXR (with AOVs).
#include "cli_fixture.h"

#include "render/frame_settings.h"
#include "render/tile_file.h"
#include "util/scene_error.h"

#include <gtest/gtest.h>

#include <string>

namespace lray {
namespace {

using namespace cli_test;
namespace fs = std::filesystem;

// Shadows, an area light, reflection and a CSG: every kind of sample.
const char *kScene = R"(
scene_info = SceneInfo() { image_width = 72, image_height = 53, frames = 6 }
function scene(clock)
  local s = Scene() { camera = Perspective(50, 72 / 53) { transform = LookAt(Vector(0, 2, -6), origin, y) } }
  s:add_entity(Plane(Translate(Vector(0, -1, 0))))
  s:add_entity(Difference { Cube(Rotate(y, 30 + 40 * clock)), Sphere(Scale(0.65)) })
  s:add_entity(Sphere(Translate(Vector(1.6, 0, 0.5)) * Scale(0.6)) {
    texture = Texture() { finish = Finish() { reflection = 0.5 } } })
  s:add_light(Light() { transform = Translate(Vector(-3, 5, -4)), rows = 3, cols = 3, area = true })
  return s
end
)";

class Farm : public LrayCli {};

TEST_F(Farm, TilesMergeIntoTheSameBytesAsTheWholeFrame) {
  fs::path scene = writeScene("f.lua", kScene);
  struct Mode {
    const char *args;
    const char *file;
  };
  const Mode modes[] = {
      {"--frames 2 -s 2", "f0002.png"},
      {"--frames 2 -s 2 --backend kdtree", "f0002.png"},
      {"--frames 3 --noise-threshold 0.03 --max-samples 64", "f0003.png"},
      {"--frames 3 --noise-threshold 0.03 --max-samples 64 --backend kdtree", "f0003.png"},
      {"--frames 3 --noise-threshold 0.03 --min-samples 1 --max-samples 64", "f0003.png"},
      {"--frames 1 --format exr --aovs -s 2", "f0001.exr"},
      {"--frames 1 --linear --format tga", "f0001.tga"},
      // Motion blur (the CSG turns with the clock): each sample's time comes
      // from its pixel and index, whatever the tile.
      {"--frames 2 -s 2 --shutter 0.8 --motion-steps 3", "f0002.png"},
      {"--frames 2 -s 2 --shutter 0.8 --backend kdtree", "f0002.png"},
  };
  for (const Mode &m : modes) {
    fs::path whole = dir_ / "whole", tiles = dir_ / "tiles";
    fs::remove_all(whole);
    fs::remove_all(tiles);
    ASSERT_EQ(runLray(scene.string() + " " + whole.string() + " -q " + m.args).status, 0);
    for (int i = 0; i < 3; ++i) {
      Result r = runLray(scene.string() + " " + tiles.string() + " -q " + m.args + " --tile " +
                         std::to_string(i) + "/3");
      ASSERT_EQ(r.status, 0) << r.output;
    }
    EXPECT_TRUE(fs::exists(tiles / (fs::path(m.file).stem().string() + ".tile-1-of-3.exr")));
    Result merged = runMerge(tiles.string());
    ASSERT_EQ(merged.status, 0) << merged.output;
    const std::string a = readFile(whole / m.file), b = readFile(tiles / m.file);
    ASSERT_FALSE(a.empty()) << m.args;
    EXPECT_TRUE(a == b) << "the merged frame differs from the whole one: " << m.args;
    // The tiles are gone, the frame is all that is left.
    size_t files = 0;
    for (const auto &e : fs::directory_iterator(tiles)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u) << m.args;
  }
  // Crops too, of any shape (here two columns and a corner split).
  fs::path whole = dir_ / "whole2", crops = dir_ / "crops";
  ASSERT_EQ(runLray(scene.string() + " " + whole.string() +
                    " -q --frames 4 --noise-threshold 0.03 --max-samples 64")
                .status,
            0);
  for (const char *c : {"0:0:30:53", "30:0:72:20", "30:20:72:53"})
    ASSERT_EQ(runLray(scene.string() + " " + crops.string() +
                      " -q --frames 4 --noise-threshold 0.03 --max-samples 64 --crop " + c)
                  .status,
              0);
  ASSERT_EQ(runMerge(crops.string() + " --keep-tiles").status, 0);
  EXPECT_TRUE(readFile(whole / "f0004.png") == readFile(crops / "f0004.png"));
  EXPECT_TRUE(fs::exists(crops / "f0004.crop-30-0-72-20.exr"));
  // The centre-first pass decides from its neighbours: crops stitch the same.
  fs::path whole1 = dir_ / "whole1", crops1 = dir_ / "crops1";
  const std::string centreFirst =
      " -q --frames 4 --noise-threshold 0.02 --min-samples 1 --max-samples 64";
  ASSERT_EQ(runLray(scene.string() + " " + whole1.string() + centreFirst).status, 0);
  for (const char *c : {"0:0:30:53", "30:0:72:20", "30:20:72:53"})
    ASSERT_EQ(runLray(scene.string() + " " + crops1.string() + centreFirst + " --crop " + c).status,
              0);
  ASSERT_EQ(runMerge(crops1.string()).status, 0);
  EXPECT_TRUE(readFile(whole1 / "f0004.png") == readFile(crops1 / "f0004.png"));
}

TEST_F(Farm, MergeNamesWhatIsMissingOrWrong) {
  fs::path scene = writeScene("f.lua", kScene);
  fs::path out = dir_ / "o";
  for (int i : {0, 2})
    ASSERT_EQ(runLray(scene.string() + " " + out.string() + " -q --frames 0 --tile " +
                      std::to_string(i) + "/4").status, 0);
  Result r = runMerge(out.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.output,
            "lray-merge: error: f0000.png: missing f0000.tile-1-of-4.exr, f0000.tile-3-of-4.exr\n");
  EXPECT_FALSE(fs::exists(out / "f0000.png"));
  EXPECT_TRUE(fs::exists(out / "f0000.tile-0-of-4.exr")); // nothing removed
  // Overlapping crops.
  fs::path crops = dir_ / "c";
  for (const char *c : {"0:0:40:53", "30:0:72:53"})
    ASSERT_EQ(runLray(scene.string() + " " + crops.string() + " -q --frames 0 --crop " + c).status,
              0);
  r = runMerge(crops.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("f0000.png: tiles overlap at pixel (30, 0)"), std::string::npos)
      << r.output;
  // An EXR that is not a tile.
  fs::path other = dir_ / "x";
  ASSERT_EQ(runLray(scene.string() + " " + other.string() + " -q --frames 0 --format exr").status,
            0);
  fs::rename(other / "f0000.exr", other / "f0000.tile-0-of-1.exr");
  r = runMerge(other.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("not a tile written by lray --tile or --crop"), std::string::npos)
      << r.output;
  // Tiles of two different renders of one frame (other samples).
  fs::path mixed = dir_ / "m";
  ASSERT_EQ(
      runLray(scene.string() + " " + mixed.string() + " -q --frames 0 -s 1 --tile 0/2").status, 0);
  ASSERT_EQ(
      runLray(scene.string() + " " + mixed.string() + " -q --frames 0 -s 2 --tile 1/2").status, 0);
  r = runMerge(mixed.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("come from different renders"), std::string::npos) << r.output;
  // --skip-existing does not take a tile of another render for this one.
  r = runLray(scene.string() + " " + mixed.string() +
              " --frames 0 -s 2 --tile 0/2 --skip-existing");
  EXPECT_EQ(r.output.find("exists: skipped"), std::string::npos) << r.output;
  EXPECT_EQ(runMerge(mixed.string()).status, 0);
  // A tile renamed to claim another frame (or any other file) is refused.
  fs::path renamed = dir_ / "r";
  ASSERT_EQ(runLray(scene.string() + " " + renamed.string() + " -q --frames 0 --tile 0/1").status,
            0);
  fs::rename(renamed / "f0000.tile-0-of-1.exr", renamed / "f.tile-0-of-1.exr");
  r = runMerge(renamed.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("it names the frame 'f0000.png', which is not its own"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(renamed / "f0000.png"));
  // Nothing to do is not an error.
  fs::create_directories(dir_ / "empty");
  EXPECT_EQ(runMerge((dir_ / "empty").string()).status, 0);
}

TEST_F(Farm, FrameStepsAndSkipExistingResumeAnAnimation) {
  fs::path scene = writeScene("f.lua", kScene);
  fs::path out = dir_ / "o";
  ASSERT_EQ(runLray(scene.string() + " " + out.string() + " -q --frames 1:5:2").status, 0);
  for (int f = 0; f < 6; ++f)
    EXPECT_EQ(fs::exists(out / ("f000" + std::to_string(f) + ".png")), f % 2 == 1) << f;
  const std::string before = readFile(out / "f0003.png");
  // A truncated frame (a crash mid-write of some other tool) and a frame of
  // the wrong size are rendered again; complete ones are skipped.
  {
    std::ofstream(out / "f0001.png", std::ios::binary | std::ios::trunc)
        << before.substr(0, before.size() / 2);
  }
  ASSERT_EQ(
      runLray(scene.string() + " " + (dir_ / "small").string() + " -q --frames 5 -w 20").status, 0);
  fs::copy_file(dir_ / "small" / "f0005.png", out / "f0005.png",
                fs::copy_options::overwrite_existing);
  Result r = runLray(scene.string() + " " + out.string() + " --frames 0:5 --skip-existing");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("f0003.png exists: skipped"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("f0001.png exists"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("f0005.png exists"), std::string::npos) << r.output;
  // Every frame now complete and as a fresh render gives it.
  fs::path fresh = dir_ / "fresh";
  ASSERT_EQ(runLray(scene.string() + " " + fresh.string() + " -q").status, 0);
  for (int f = 0; f < 6; ++f) {
    const std::string name = "f000" + std::to_string(f) + ".png";
    EXPECT_TRUE(readFile(out / name) == readFile(fresh / name)) << name;
  }
  // Tiles are skipped the same way.
  fs::path tiles = dir_ / "t";
  ASSERT_EQ(runLray(scene.string() + " " + tiles.string() + " -q --frames 0 --tile 1/2").status, 0);
  r = runLray(scene.string() + " " + tiles.string() + " --frames 0 --tile 1/2 --skip-existing");
  EXPECT_NE(r.output.find("f0000.tile-1-of-2.exr exists: skipped"), std::string::npos) << r.output;
}

TEST_F(Farm, TileAndCropMistakesAreReadable) {
  fs::path scene = writeScene("f.lua", kScene);
  const std::string base = scene.string() + " " + (dir_ / "o").string() + " -q ";
  auto error = [&](const std::string &args) { return runLray(base + args).output; };
  EXPECT_EQ(error("--tile 4/4"), "lray: error: --tile '4/4': I must be below N (tiles are numbered "
                                 "from 0) (run 'lray --help' for usage)\n");
  EXPECT_EQ(error("--tile 1-4"), "lray: error: --tile '1-4': expected I/N, tile I (0-based) of N "
                                 "(run 'lray --help' for usage)\n");
  EXPECT_EQ(error("--tile 0/5"), "lray: error: --tile 0/5: a frame 53 pixels high has 4 rows of "
                                 "16-pixel tiles, so at most 4 tiles\n");
  EXPECT_EQ(error("--crop 0:0:0:5"), "lray: error: --crop '0:0:0:5': the window is empty (x1 must "
                                     "be above x0, y1 above y0) (run 'lray --help' for usage)\n");
  EXPECT_EQ(error("--crop 0:0:80:5"),
            "lray: error: --crop 0:0:80:5: the window reaches outside the 72 x 53 frame\n");
  EXPECT_EQ(
      error("--frames 0:4:0"),
      "lray: error: --frames '0:4:0': the step must be 1 or more (run 'lray --help' for usage)\n");
  EXPECT_EQ(error("--crop 0:0:8:8 --tile 0/2"), "lray: error: --tile and --crop both choose the "
                                                "pixels: give one (run 'lray --help' for usage)\n");
}

TEST(TileBand, BandsOfWholeTileRowsCoverTheFrameOnce) {
  for (int height : {1, 16, 17, 53, 480})
    for (int n = 1; n <= (height + 15) / 16; ++n) {
      int next = 0;
      for (int i = 0; i < n; ++i) {
        PixelWindow w = tileBand(i, n, 100, height);
        EXPECT_EQ(w.y0, next);
        EXPECT_EQ(w.y0 % kTileSize, 0);
        EXPECT_GT(w.y1, w.y0);
        EXPECT_EQ(w.x0, 0);
        EXPECT_EQ(w.x1, 100);
        next = w.y1;
      }
      EXPECT_EQ(next, height);
    }
  EXPECT_THROW(tileBand(0, 5, 10, 64), SceneError);
}

} // namespace
} // namespace lray
