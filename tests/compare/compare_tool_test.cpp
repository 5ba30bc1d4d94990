// lray-compare as a user runs it: a suite of scenes approved, passing,
// failing after a change, a scene that does not render, one that never
// ends, the JUnit and HTML reports, and usage errors (exit 2).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct ToolRun {
  int status;
  std::string out, err;
};

std::string slurp(const fs::path &p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

ToolRun compare(const fs::path &dir, const std::string &args) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" LRAY_COMPARE_BINARY "' " + args + " >out.txt 2>err.txt";
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "out.txt"), slurp(dir / "err.txt")};
}

void write(const fs::path &p, const std::string &text) { std::ofstream(p) << text; }

std::string scene(double light) {
  return R"(scene_info = SceneInfo() { image_width = 32, image_height = 24, samples = 1 }
function scene(clock)
  local s = Scene() { camera = Perspective(50, 32 / 24) {
    transform = LookAt(Vector(0, 1, -3), Vector(0, 0.3, 0), y) } }
  s:add_entity(Sphere(Scale(0.6)) {
    texture = Texture() { pigment = ColorPigment(Color(0.8, 0.5, 0.2)) } })
  s:add_light(Light() { color = grey()" +
         std::to_string(light) + R"(), transform = Translate(Vector(-3, 5, -4)) })
  return s
end
)";
}

const char *kNoisy = R"(scene_info = SceneInfo() { image_width = 24, image_height = 16, samples = 3,
                                         integrator = "path", max_depth = 3 }
function scene(clock)
  local s = Scene() { background_color = Color(0.3, 0.3, 0.4),
    camera = Perspective(50, 1.5) { transform = LookAt(Vector(0, 1, -3), Vector(0, 0.3, 0), y) } }
  s:add_entity(Sphere(Scale(0.6)) {
    texture = Texture() { finish = Finish() { ambient = grey(0) } } })
  s:add_light(Light() { rows = 2, cols = 2, area = true, transform = Translate(Vector(-3, 5, -4)) })
  return s
end
)";

const char *kSuite = R"(# a suite as a user writes it
[defaults]
options = ["-t", "2"]

[[case]]
name = "ok"
scene = "scene.lua"
approved = "approved/ok.png"
backends = ["embree", "kdtree"]

[[case]]
name = "noisy"
scene = "noisy.lua"
approved = "approved/noisy.exr"
metric = "noise"
threshold = 0.01
approve_options = ["--seed", "9"]

[[case]]
name = "noisy_png"
scene = "noisy.lua"
approved = "approved/noisy.png"
metric = "noise"
second_seed = 5           # 8 bits, no variance: a second render gives it
approve_options = ["--seed", "9"]

[[case]]
name = "broken"
scene = "broken.lua"
approved = "approved/broken.png"

[[case]]
name = "endless"
scene = "endless.lua"
approved = "approved/endless.png"
timeout = 1
)";

class CompareTool : public ::testing::Test {
protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("lray_compare_tool_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
           std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    write(dir / "scene.lua", scene(1));
    write(dir / "noisy.lua", kNoisy);
    write(dir / "broken.lua", "scene_info = SceneInfo() {\n  image_width = 'wide' }\n");
    write(dir / "endless.lua", "while true do end\n");
    write(dir / "suite.toml", kSuite);
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir;
};

} // namespace

TEST_F(CompareTool, ApprovesPassesFailsAfterAChangeAndReports) {
  ToolRun r = compare(dir, "--suite suite.toml --approve --only ok.embree --only ok.kdtree "
                          "--only noisy --only noisy_png");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir / "approved/ok.png"));
  EXPECT_TRUE(fs::exists(dir / "approved/noisy.exr"));
  EXPECT_TRUE(fs::exists(dir / "approved/noisy.png"));

  r = compare(dir, "--suite suite.toml --junit results.xml --html report");
  EXPECT_EQ(r.status, 1); // broken and endless
  EXPECT_NE(r.out.find("PASS  ok.embree"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("PASS  ok.kdtree"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("PASS  noisy:"), std::string::npos) << r.out << r.err; // seed 0 vs 9
  EXPECT_NE(r.out.find("PASS  noisy_png:"), std::string::npos) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir / "lray-compare-out/noisy_png.second/frames/noisy.png"));
  // lray's own message, with the script's file and line.
  EXPECT_NE(r.err.find("ERROR broken: render failed: lray exited with status 1"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("broken.lua:1: SceneInfo: attribute 'image_width' expects an integer"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("ERROR endless: render failed: the render took longer than 1 s"),
            std::string::npos)
      << r.err;
  const std::string xml = slurp(dir / "results.xml");
  EXPECT_NE(xml.find("tests=\"6\" failures=\"0\" errors=\"2\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<testcase classname=\"suite\" name=\"ok.kdtree\""), std::string::npos);
  EXPECT_NE(xml.find("<error message=\"render failed"), std::string::npos);
  const std::string html = slurp(dir / "report/index.html");
  EXPECT_NE(html.find("suite: 4 of 6 cases pass"), std::string::npos);
  EXPECT_NE(html.find("src=\"noisy/difference.png\""), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "report/ok.embree/new.png"));
  EXPECT_TRUE(fs::exists(dir / "report/noisy/approved.png"));

  // The light 2 % brighter: both backends fail, with the figures.
  write(dir / "scene.lua", scene(1.02));
  r = compare(dir, "--suite suite.toml --only ok.embree --only ok.kdtree --junit results.xml");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("FAIL  ok.embree: pixel:"), std::string::npos) << r.err;
  EXPECT_NE(slurp(dir / "results.xml").find("tests=\"2\" failures=\"2\" errors=\"0\""),
            std::string::npos);

  // Two images directly, and a metric that tolerates the change.
  r = compare(dir, "lray-compare-out/ok.embree/frames/scene.png approved/ok.png --metric psnr "
                   "--threshold 30");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  r = compare(dir, "lray-compare-out/ok.embree/frames/scene.png approved/ok.png");
  EXPECT_EQ(r.status, 1);
}

// lray leaves NaN and infinite samples out of the image and counts them
// (--stats): the tool fails such a render whatever the image says, and
// never approves it. Here an emission and a light near the largest double
// overflow when the shading equation adds them.
TEST_F(CompareTool, ARenderWithNonFiniteSamplesFailsAndIsNeverApproved) {
  write(dir / "overflow.lua", R"(scene_info = SceneInfo() { image_width = 8, image_height = 8 }
function scene()
  local s = Scene() { camera = Perspective(40, 1) {
    transform = LookAt(Vector(0, 0, -5), Vector(0, 0, 0), y) } }
  local huge = Color(1.7e308, 1.7e308, 1.7e308)
  s:add_entity(Sphere() { texture = Texture() { finish = Finish() { emission = huge } } })
  s:add_light(Light() { color = huge, transform = Translate(Vector(0, 0, -5)) })
  return s
end
)");
  write(dir / "overflow.toml", "[[case]]\nname = \"overflow\"\nscene = \"overflow.lua\"\n"
                               "approved = \"approved/overflow.png\"\n"
                               "options = [\"--stats\", \"mine.json\"]\n");
  ToolRun r = compare(dir, "--suite overflow.toml --approve");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_FALSE(fs::exists(dir / "approved/overflow.png"));
  EXPECT_NE(r.err.find("overflow: 16 samples were not finite (NaN or infinite"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("--approve"), std::string::npos) << r.err; // no advice to approve it
  // The tool's own --stats file, not the one the options name.
  EXPECT_TRUE(fs::exists(dir / "lray-compare-out/overflow/stats.json"));
  EXPECT_FALSE(fs::exists(dir / "mine.json"));

  // Against an approved image: the count, then the comparison's verdict.
  fs::create_directories(dir / "approved");
  fs::copy_file(dir / "lray-compare-out/overflow/frames/overflow.png",
                dir / "approved/overflow.png");
  r = compare(dir, "--suite overflow.toml");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("FAIL  overflow: 16 samples were not finite (NaN or infinite; lray left "
                       "them out of the image); pixel:"),
            std::string::npos)
      << r.err;
}

TEST_F(CompareTool, UsageAndSuiteErrorsExitTwoNamingTheLine) {
  write(dir / "bad.toml", "[[case]]\nname = \"a\"\nscene = \"scene.lua\"\n"
                          "approved = \"a.png\"\ntreshold = 0.1\n");
  ToolRun r = compare(dir, "--suite bad.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.toml:5: unknown key 'treshold'"), std::string::npos) << r.err;
  write(dir / "bad.toml", "[[case]]\nname = \"a\"\nscene = \"scene.lua\"\n"
                          "approved = \"a.png\"\nmetric = \"noise\"\nthreshold = 2\n");
  r = compare(dir, "--suite bad.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.toml:1: the noise test's false-alarm rate"), std::string::npos)
      << r.err;
  EXPECT_EQ(compare(dir, "").status, 2);
  EXPECT_EQ(compare(dir, "a.png").status, 2);
  EXPECT_EQ(compare(dir, "--suite suite.toml --only nosuch").status, 2);
  EXPECT_EQ(compare(dir, "a.png b.png --name ../escape --html report").status, 2);
  // A missing image is the case's error (exit 1), not a usage error.
  r = compare(dir, "missing.png approved/missing.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot read 'missing.png'"), std::string::npos) << r.err;
}
