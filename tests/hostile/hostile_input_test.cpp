// The hostile-input suite (CTest label "hostile"): scene files and command
// lines a careless or hostile author could hand a render farm, each run as
// a real `lray` process. Every case asserts that the process ends within a
// bound, its exit status, one readable message naming the file and line
// (or the path or value), its peak memory, and that the output folder
// holds nothing but complete images.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace lray {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;       ///< exit status; -1 if killed
  bool timedOut = false;
  double seconds = 0;
  long peakKiB = 0;      ///< the child's peak resident set
  std::string output;    ///< stdout + stderr
};

/// Runs lray with `args`, killing it after `limitSeconds`; with
/// `fileSizeLimit`, no file it writes may grow past that many bytes (a
/// full disk, as far as the process can tell: writes fail with EFBIG).
Outcome runProgram(const std::string &binary, const std::vector<std::string> &args,
                   double limitSeconds, rlim_t fileSizeLimit = RLIM_INFINITY,
                   rlim_t addressSpaceLimit = RLIM_INFINITY) {
  int pipeFds[2];
  if (pipe(pipeFds) != 0) return {};
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = fork();
  if (pid == 0) {
    if (fileSizeLimit != RLIM_INFINITY) {
      signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{fileSizeLimit, fileSizeLimit};
      setrlimit(RLIMIT_FSIZE, &limit);
    }
    if (addressSpaceLimit != RLIM_INFINITY) {
      const rlimit limit{addressSpaceLimit, addressSpaceLimit};
      setrlimit(RLIMIT_AS, &limit);
    }
    dup2(pipeFds[1], 1);
    dup2(pipeFds[1], 2);
    close(pipeFds[0]);
    close(pipeFds[1]);
    std::vector<char *> argv{const_cast<char *>(binary.c_str())};
    for (const std::string &a : args) argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  close(pipeFds[1]);
  Outcome out;
  const auto deadline = start + std::chrono::duration<double>(limitSeconds);
  char buf[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      out.timedOut = true;
      kill(pid, SIGKILL);
      break;
    }
    pollfd p{pipeFds[0], POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
    const ssize_t n = read(pipeFds[0], buf, sizeof buf);
    if (n <= 0) break;
    out.output.append(buf, static_cast<size_t>(n));
  }
  close(pipeFds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  out.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  out.peakKiB = usage.ru_maxrss;
  return out;
}

Outcome runLray(const std::vector<std::string> &args, double limitSeconds,
                rlim_t fileSizeLimit = RLIM_INFINITY) {
  return runProgram(LRAY_BINARY, args, limitSeconds, fileSizeLimit);
}

/// lray-merge, built beside lray.
Outcome runMerge(const std::vector<std::string> &args, double limitSeconds) {
  return runProgram((fs::path(LRAY_BINARY).parent_path() / "lray-merge").string(), args,
                    limitSeconds);
}

/// A valid PNG signature and IHDR chunk for 100000 x 100000 RGB, and no data.
std::string hugePngHeader() {
  std::string png("\x89PNG\r\n\x1a\n", 8);
  unsigned char ihdr[] = {0, 0, 0, 13, 'I', 'H', 'D', 'R', 0, 1, 0x86, 0xa0, 0, 1, 0x86,
                          0xa0, 8, 2, 0, 0, 0, 0, 0, 0, 0};
  // The chunk's CRC-32 (over type and data), so the header itself is valid.
  uint32_t crc = 0xffffffffu;
  for (int i = 4; i < 21; ++i) {
    crc ^= ihdr[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1)));
  }
  crc ^= 0xffffffffu;
  for (int i = 0; i < 4; ++i) ihdr[21 + i] = static_cast<unsigned char>(crc >> (24 - 8 * i));
  png.append(reinterpret_cast<const char *>(ihdr), sizeof ihdr);
  return png;
}

class Hostile : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lray_hostile_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string &name, const std::string &text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string out() const { return (dir_ / "out").string(); }

  /// Runs the case and checks what every case must hold.
  Outcome expectRefused(const std::vector<std::string> &args, int status,
                        const std::string &message, double limitSeconds = 20,
                        long peakMiB = 1024) {
    Outcome o = runLray(args, limitSeconds);
    EXPECT_FALSE(o.timedOut) << "still running after " << limitSeconds << " s";
    EXPECT_EQ(o.status, status) << o.output;
    EXPECT_NE(o.output.find(message), std::string::npos) << o.output;
    EXPECT_LT(o.peakKiB, peakMiB * 1024) << "peak memory";
    // One readable paragraph: no C++ exception names, no library noise.
    EXPECT_EQ(o.output.find("std::"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("libpng error"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.rfind("lray: error: ", 0), 0u) << o.output;
    // Nothing half-written: the output folder holds no image and no temporary file.
    if (fs::exists(out()))
      for (const auto &e : fs::directory_iterator(out())) ADD_FAILURE() << "left " << e.path();
    return o;
  }

  fs::path dir_;
};

const std::string kScene = "\nfunction scene() return Scene() end\n";

TEST_F(Hostile, ScriptMemoryIsCappedAndTheErrorNamesTheLine) {
  const std::string s =
      write("mem.lua",
            "local t = {}\nfor i = 1, 1e9 do\n  t[i] = string.rep('x', 1000) .. i\nend" + kScene);
  expectRefused({s, out(), "--script-memory", "128M"}, 1,
                "mem.lua:3: the script needed more than 128 MiB of memory and was stopped "
                "(raise the limit with --script-memory)",
                20, 400);
}

TEST_F(Hostile, MeshArraysCountAgainstTheScriptMemory) {
  // One 100,000-vertex table copied into ever more meshes: the Lua heap
  // stays small, the meshes' C++ arrays do not.
  const std::string s = write(
      "meshes.lua", "local big = {}\nfor i = 1, 100000 do big[i] = {i, 0, 0} end\n"
                    "local keep = {}\nfor i = 1, 100000 do\n  local m = Mesh()\n"
                    "  m.vertices = big\n  keep[i] = m\nend" + kScene);
  // Whichever allocation crosses the limit first, a mesh's arrays or a
  // Lua object, the error is blamed on the line that made the meshes.
  const Outcome o =
      expectRefused({s, out(), "--script-memory", "256M"}, 1, "meshes.lua:6: ", 60, 600);
  EXPECT_NE(o.output.find("the script needed more than 256 MiB of memory"), std::string::npos)
      << o.output;
}

TEST_F(Hostile, AMeshRebuiltEveryFrameDoesNotAccumulateCharges) {
  // Meshes dropped by the script are uncharged when collected.
  const std::string s =
      write("anim.lua",
            "scene_info = SceneInfo() { image_width = 4, image_height = 4, frames = 10 }\n"
            "local big = {}\nfor i = 1, 100000 do big[i] = {i, 0, 0} end\n"
            "function scene(clock)\n  for k = 1, 20 do local m = Mesh(); m.vertices = big end\n"
            "  collectgarbage()\n  return Scene()\nend\n");
  const Outcome o = runLray({s, out(), "-q", "--script-memory", "128M"}, 60);
  EXPECT_EQ(o.status, 0) << o.output;
}

TEST_F(Hostile, AScriptMemoryLimitBelowLraysOwnLibrariesIsReadable) {
  const std::string s = write("tiny.lua", "local x = 1" + kScene);
  for (const char *limit : {"1", "1K", "32K"})
    expectRefused({s, out(), "--script-memory", limit}, 1,
                  " is less than the memory LRay's own libraries take (", 10, 200);
}

// Finalizer calls that fail for lack of memory (Lua then frees the userdata
// without them): the objects are still freed, nothing reads the freed
// memory (scripts/test runs this with the ASan lray too).
TEST_F(Hostile, ObjectsWhoseFinalizerCallsFailedAreStillFreed) {
  const std::string s = write(
      "fin.lua", "for round = 1, 20 do pcall(function() for i = 1, 300 do local m = Mesh() end\n"
                 "  local function f(n) return 1 + f(n + 1) end return f(1) end) end" + kScene);
  for (const char *limit : {"176K", "192K", "208K", "256K"}) {
    const Outcome o = runLray({s, out(), "-q", "-w", "4", "-H", "4", "--script-memory", limit}, 20);
    EXPECT_FALSE(o.timedOut) << limit;
    // Stopped at the limit, or finished: either way a clean exit.
    EXPECT_TRUE(o.status == 0 || o.status == 1) << limit << ": " << o.output;
    if (o.status == 1) {
      EXPECT_NE(o.output.find("fin.lua"), std::string::npos) << o.output;
    }
    EXPECT_EQ(o.output.find("Sanitizer"), std::string::npos) << o.output;
  }
}

// Chunks loaded from strings are named in messages; naming them once kept
// a copy of each chunk's whole text outside the script's memory limit
// (300 chunks of 1 MB took 300 MB under a 64 MB limit).
TEST_F(Hostile, LoadingManyBigChunksStaysWithinTheScriptMemory) {
  const std::string s = write(
      "chunks.lua", "local body = 'local x = 0 for i = 1, 20000 do x = x + i end return x --' .. "
                    "string.rep('y', 1000000)\n"
                    "for i = 1, 300 do assert(load(body .. i))() end\n"
                    "for i = 1, 20000 do assert(load('return ' .. i .. ' + 0 -- ' .. i))() end\n"
                    "error('done')" + kScene);
  const Outcome o =
      expectRefused({s, out(), "--script-memory", "64M"}, 1, "chunks.lua:4: done", 60, 150);
  (void)o;
}

// Garbage made through LRay's functions is collected before the limit is
// called exceeded (as Lua does before it refuses an allocation): a script
// whose live data is half its limit renders every frame.
TEST_F(Hostile, GarbageIsCollectedBeforeTheLimitIsCalledExceeded) {
  // Each round's vectors grow old before they die: old garbage waits for a
  // major collection, past the limit (without the collection this stopped
  // at 2.5 to 4 MiB).
  const std::string s = write(
      "garbage.lua",
      "scene_info = SceneInfo() { image_width = 4, image_height = 4, frames = 2 }\n"
      "keep = {}\nfor i = 1, 20000 do keep[i] = Vector(i, 0, 0) end\n"
      "function scene(clock)\n"
      "  for round = 1, 30 do\n"
      "    for i = 1, 20000 do keep[i] = Vector(i, round, 0) end\n"
      "  end\n"
      "  return Scene()\nend\n");
  const Outcome o = runLray({s, out(), "-q", "--script-memory", "3M"}, 60);
  EXPECT_FALSE(o.timedOut);
  EXPECT_EQ(o.status, 0) << o.output;
}

// Reading a big mesh's vertices back builds a Lua table per vertex, ten
// times the arrays they come from: the limit is checked as the table grows,
// not only when the call returns.
TEST_F(Hostile, ReadingBackABigMeshStaysWithinTheScriptMemory) {
  const std::string s = write(
      "readback.lua", "local m = Mesh()\nlocal v = {}\nfor i = 1, 200000 do v[i] = {i, 0, 0} end\n"
                      "m.vertices = v\nv = nil\ncollectgarbage()\nlocal copies = {}\n"
                      "for i = 1, 100 do copies[i] = m.vertices end" + kScene);
  // 22 MB of tables a copy: the sixth is stopped part-way.
  expectRefused({s, out(), "--script-memory", "128M"}, 1,
                "readback.lua:8: the script needed more than 128 MiB", 60, 200);
  // One call alone: a million vertices read from an OBJ (12 MB charged)
  // would be 110 MB of tables under a 48 MB limit.
  std::string obj;
  for (int i = 0; i < 1000000; ++i) obj += "v 0 0 0\n";
  obj += "f 1 2 3\n";
  write("million.obj", obj);
  const std::string one = write("readone.lua", "local m = mesh_from_obj('million.obj')\n"
                                               "local vertices = m.vertices" + kScene);
  expectRefused({one, out(), "--script-memory", "48M"}, 1,
                "readone.lua:2: the script needed more than 48 MiB", 60, 110);
}

// A script may give _G a metatable; LRay reads scene_info and scene raw, so
// an __index that fails or loops changes nothing (it once aborted, or hung
// with no time limit running).
TEST_F(Hostile, AMetatableOnTheGlobalsIsNeverCalledByLray) {
  for (const char *index : {"function() error('boom') end", "function() while true do end end"}) {
    const std::string s = write("globals.lua", "function scene() return Scene() end\n"
                                               "setmetatable(_G, {__index = " +
                                                   std::string(index) + "})\n");
    const Outcome o = runLray({s, out(), "-q", "-w", "4", "-H", "4", "--script-timeout", "2"}, 20);
    EXPECT_FALSE(o.timedOut) << index;
    EXPECT_EQ(o.status, 0) << index << ": " << o.output;
  }
}

// With --unsafe a finalizer can run in lua_close after LRay freed its
// objects' C++ parts: an LRay object it still holds reads as no object
// (scripts/test runs this with the ASan lray too).
TEST_F(Hostile, AnUnsafeFinalizerNeverSeesAFreedObject) {
  const std::string s =
      write("late.lua", "local m = Mesh() { vertices = { {0, 0, 0}, {1, 0, 0}, {0, 1, 0} } }\n"
                        "keep = setmetatable({}, {__gc = function() local ok = pcall(function() "
                        "return m.smooth end)\n"
                        "  io.write(ok and 'read' or 'refused', '\\n') end})\n" +
                            kScene.substr(1));
  const Outcome o = runLray({s, out(), "-q", "-w", "4", "-H", "4", "--unsafe"}, 20);
  EXPECT_FALSE(o.timedOut);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("refused"), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find("Sanitizer"), std::string::npos) << o.output;
}

TEST_F(Hostile, OneHugeAllocationIsRefusedNamingTheScene) {
  const std::string s = write("big.lua", "local s = string.rep('x', 1.5e9)" + kScene);
  expectRefused({s, out(), "--script-memory", "256M"}, 1,
                "big.lua: the script needed more than 256 MiB of memory", 20, 400);
}

TEST_F(Hostile, DefaultScriptMemoryIsTwoGiB) {
  const std::string s =
      write("grow.lua", "local t = {}\nfor i = 1, 1e9 do t[i] = ('y'):rep(4096) .. i end" + kScene);
  expectRefused({s, out()}, 1, "grow.lua:2: the script needed more than 2 GiB of memory", 60, 2600);
}

TEST_F(Hostile, ALongLibraryCallIsStoppedByTheWatchdog) {
  // Backtracking that would take hours, in one call the hook never sees.
  const std::string s = write("find.lua",
                              "local s = string.rep('a', 200000)\n"
                              "local r = string.find(s, '.-.-.-.-.-b')" + kScene);
  const Outcome o = expectRefused({s, out(), "--script-timeout", "0.5"}, 1,
                                  "find.lua: the script ran longer than 0.5 seconds (in a library "
                                  "call) and was stopped (raise the limit with --script-timeout)",
                                  15);
  EXPECT_LT(o.seconds, 0.5 + 2 + 3);
}

TEST_F(Hostile, AnEndlessLoopIsStoppedAtItsLine) {
  const std::string s = write("loop.lua", "local x = 0\nwhile true do x = x + 1 end" + kScene);
  expectRefused({s, out(), "--script-timeout", "0.5"}, 1,
                "loop.lua:2: the script ran longer than 0.5 seconds and was stopped", 10);
}

TEST_F(Hostile, AnEndlessLoopInSceneIsStoppedToo) {
  const std::string s = write("sl.lua", "function scene()\n  while true do end\nend\n");
  expectRefused({s, out(), "--script-timeout", "0.5"}, 1, "sl.lua:2: the script ran longer", 10);
}

TEST_F(Hostile, FinalizersAreRefusedSoNoneCanHangOrResurrect) {
  const std::string s =
      write("gc.lua", "setmetatable({}, { __gc = function() while true do end end })" + kScene);
  expectRefused({s, out(), "--script-timeout", "1"}, 1,
                "gc.lua:1: setmetatable: __gc finalizers are not allowed in scene scripts", 10);
}

TEST_F(Hostile, AFinalizerAddedAfterSetmetatableNeverRuns) {
  // Lua marks an object for finalization only at setmetatable: adding
  // __gc later is inert, and the render completes.
  const std::string s =
      write("late.lua",
            "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
            "local mt = {}\nsetmetatable({}, mt)\nmt.__gc = function() while true do end end\n"
            "collectgarbage()" +
                kScene);
  const Outcome o = runLray({s, out(), "--script-timeout", "1", "-q"}, 10);
  EXPECT_FALSE(o.timedOut);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::is_regular_file(fs::path(out()) / "late.png"));
}

TEST_F(Hostile, NoFinalizerCanBeSwappedIntoAFileOrAnLrayObject) {
  // Userdata carry C finalizers; their metatables are out of reach, so no
  // Lua function can be made to run with the hooks off.
  const std::string s = write(
      "swap.lua", "local f = io.open('swap.lua')\nlocal mt = getmetatable(f)\n"
                  "mt.__gc = function() while true do end end" + kScene);
  expectRefused({s, out(), "--script-timeout", "1"}, 1, "swap.lua:3: attempt to index a nil value",
                10);
  const std::string t = write(
      "swap2.lua", "local mt = getmetatable(Sphere())\n"
                   "mt.__gc = function() while true do end end" + kScene);
  expectRefused({t, out(), "--script-timeout", "1"}, 1, "swap2.lua:2: attempt to index a nil value",
                10);
}

TEST_F(Hostile, DeeplyNestedPigmentsAreAnErrorNotACrash) {
  const std::string s = write(
      "nest.lua",
      "local p = ColorPigment(red)\nfor i = 1, 100000 do\n"
      "  p = CheckerPigment2D() { pigment1 = p, pigment2 = ColorPigment(blue) }\nend\n"
      "function scene()\n  local s = Scene()\n"
      "  s:add_entity(Sphere() { texture = Texture() { pigment = p } })\n  return s\nend\n");
  expectRefused({s, out()}, 1, "nest.lua:", 20);
}

TEST_F(Hostile, DeeplyNestedCsgIsAnErrorNotACrash) {
  for (const char *op : {"Union", "Difference"}) {
    const std::string s =
        write("csg.lua",
              std::string("local u = Sphere()\nfor i = 1, 100000 do\n  u = ") + op +
                  " { u, Cube() }\nend\n"
                  "function scene()\n  local s = Scene()\n  s:add_entity(u)\n  return s\nend\n");
    expectRefused({s, out()}, 1,
                  "csg.lua:3: " + std::string(op) + ": CSG nodes are nested more than 64 deep", 20);
  }
}

TEST_F(Hostile, ASharedUnionThatDoublesFortyTimesIsRefused) {
  const std::string s = write(
      "double.lua", "local u = Sphere()\nfor i = 1, 40 do u = Union { u, u } end\n"
                    "function scene()\n  local s = Scene()\n  s:add_entity(u)\n  return s\nend\n");
  expectRefused({s, out()}, 1, "double.lua:2: Union: expands to more than 2097152 solids", 30,
                1500);
}

TEST_F(Hostile, AHugeCsgTreeIsRefusedNamingTheLine) {
  const std::string s = write(
      "big.lua",
      "local list = {}\nfor i = 1, 200000 do list[i] = Sphere() end\n"
      "function scene()\n  local s = Scene()\n  s:add_entity(Merge(list))\n  return s\nend\n");
  expectRefused({s, out()}, 1, "big.lua:5: Merge: ", 20);
}

TEST_F(Hostile, AnAbsurdAreaLightIsRefusedNamingTheKnob) {
  const std::string s = write(
      "light.lua", "function scene()\n  local s = Scene()\n"
                   "  s:add_light(Light() { rows = 100000, cols = 100000, area = true })\n"
                   "  return s\nend\n");
  expectRefused({s, out()}, 1, "--max-light-samples", 10);
}

TEST_F(Hostile, AnAbsurdImageSizeIsRefused) {
  const std::string s = write("size.lua", "scene_info = SceneInfo() { image_width = 1000000, "
                                          "image_height = 1000000 }" + kScene);
  expectRefused({s, out()}, 1, "--max-pixels", 10);
}

TEST_F(Hostile, AnAbsurdAdaptiveBudgetIsRefused) {
  const std::string s = write("ad.lua", kScene);
  expectRefused({s, out(), "--noise-threshold", "0.01", "--max-samples", "100000000"}, 1,
                "lower --max-samples or raise --max-pixels", 10);
}

TEST_F(Hostile, ADeviceGivenAsAnObjIsRefusedNamingThePath) {
  const std::string s = write("dev.lua", "local m = mesh_from_obj('/dev/zero')" + kScene);
  expectRefused({s, out()}, 1, "/dev/zero", 10, 200);
}

TEST_F(Hostile, AFolderGivenAsAnObjIsRefusedNamingThePath) {
  fs::create_directories(dir_ / "folder.obj");
  const std::string s = write("dir.lua", "local m = mesh_from_obj('folder.obj')" + kScene);
  expectRefused({s, out()}, 1, "folder.obj", 10);
}

TEST_F(Hostile, OversizedSceneAndObjFilesAreRefusedBeforeReading) {
  std::ofstream(dir_ / "big.obj") << std::string(5000, '#') << "\n";
  const std::string s = write("bo.lua", "\nlocal m = mesh_from_obj('big.obj')" + kScene);
  expectRefused(
      {s, out(), "--max-file-size", "4K"}, 1,
      "bo.lua:2: mesh_from_obj: big.obj: 5001 bytes, more than the limit of 4096 (raise it "
      "with --max-file-size)",
      10);
  const std::string t = write("long.lua", "-- " + std::string(5000, 'x') + kScene);
  expectRefused({t, out(), "--max-file-size", "4K"}, 1,
                "long.lua: " + std::to_string(fs::file_size(t)) +
                    " bytes, more than the limit of 4096 for a scene file",
                10);
}

TEST_F(Hostile, AMissingObjNamesThePathAndLine) {
  const std::string s = write("miss.lua", "\nlocal m = mesh_from_obj('nothere.obj')" + kScene);
  expectRefused({s, out()}, 1, "miss.lua:2", 10);
}

TEST_F(Hostile, APngWhoseHeaderClaimsAHugeImageIsRefusedBeforeAllocating) {
  write("huge.png", hugePngHeader());
  const std::string s = write(
      "img.lua", "function scene()\n  local s = Scene()\n"
                 "  s:add_entity(Sphere() { texture = Texture() { pigment = "
                 "ImagePigment2D('huge.png') } })\n  return s\nend\n");
  expectRefused({s, out()}, 1, "huge.png' is 100000 x 100000 texels, more than the limit", 10, 400);
}

TEST_F(Hostile, ATruncatedPngIsOneMessage) {
  write("cut.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16));
  const std::string s = write(
      "cut.lua", "function scene()\n  local s = Scene()\n"
                 "  s:add_entity(Sphere() { texture = Texture() { pigment = "
                 "ImagePigment2D('cut.png') } })\n  return s\nend\n");
  expectRefused({s, out()}, 1, "cut.png", 10);
}

TEST_F(Hostile, ABinaryChunkSceneIsRefusedNamingTheFile) {
  const std::string s = write("bin.lua", std::string("\x1bLua\x54\x00", 6));
  expectRefused({s, out()}, 1, "bin.lua", 10);
}

// The sandbox's checks live in C (bindings/sandbox.cpp): a script that
// first replaces every global it could (error, type, rawget, tostring,
// select, string, pcall, ... and the sandboxed functions' own names)
// talks none of them out of its check.
const std::string kEveryGlobalReplaced =
    "scene_info = SceneInfo() { image_width = 2, image_height = 2 }\n"
    "local open, lines, setmt, getmt, ld, ldfile, dofl = io.open, io.lines, setmetatable,\n"
    "  getmetatable, load, loadfile, dofile\n"
    "local Scene_ = Scene\n"
    "local keys = {}\n"
    "for k in pairs(_G) do keys[#keys + 1] = k end\n"
    "local liar = function() return 'table' end\n"
    "for _, k in ipairs(keys) do if k ~= '_G' and k ~= 'scene_info' then _G[k] = liar end end\n"
    "function scene() return Scene_() end\n";

TEST_F(Hostile, WritingIsRefusedEvenWithEveryGlobalReplaced) {
  const std::string s = write("w.lua", kEveryGlobalReplaced + "local f = open('x.txt', 'w')\n");
  expectRefused({s, out()}, 1, "w.lua:10: io.open: only read mode is allowed", 10);
  EXPECT_FALSE(fs::exists(dir_ / "x.txt"));
  const std::string a = write("a.lua", kEveryGlobalReplaced + "local f = open('y.txt', 'a+')\n");
  expectRefused({a, out()}, 1, "a.lua:10: io.open: only read mode is allowed", 10);
  EXPECT_FALSE(fs::exists(dir_ / "y.txt"));
}

TEST_F(Hostile, FinalizersAreRefusedEvenWithEveryGlobalReplaced) {
  const std::string s = write(
      "gc.lua", kEveryGlobalReplaced + "setmt({}, { __gc = function() while true do end end })\n");
  expectRefused({s, out(), "--script-timeout", "1"}, 1,
                "gc.lua:10: setmetatable: __gc finalizers are not allowed", 10);
  // A metatable whose own metatable offers __gc is no way round the check
  // either: Lua looks __gc up raw, as the check does, and the object is
  // not marked for finalization.
  const std::string t = write(
      "gc2.lua", kEveryGlobalReplaced +
                     "local mt = setmt({}, { __index = { __gc = function() while true do end "
                     "end } })\nsetmt({}, mt)\n");
  const Outcome o = runLray({t, out(), "--script-timeout", "1", "-q"}, 10);
  EXPECT_FALSE(o.timedOut);
  EXPECT_EQ(o.status, 0) << o.output;
}

TEST_F(Hostile, ResurrectingAConvertedObjectIsRefusedEvenWithEveryGlobalReplaced) {
  // The first round's trick: a finalizer that hands the converter an
  // object it already freed. No finalizer can be installed, so no
  // use-after-free (run under ASan by scripts/test).
  const std::string s = write(
      "res.lua", kEveryGlobalReplaced +
                     "local keep\nsetmt({ t = Translate(Vector(1, 0, 0)) }, { __gc = function(o) "
                     "keep = o.t end })\n");
  expectRefused({s, out(), "--script-timeout", "1"}, 1,
                "res.lua:11: setmetatable: __gc finalizers are not allowed", 10);
}

TEST_F(Hostile, UserdataMetatablesStayHiddenEvenWithEveryGlobalReplaced) {
  const std::string s = write(
      "mt.lua", kEveryGlobalReplaced +
                    "local f = open('mt.lua')\nlocal mt = getmt(f)\nmt.__gc = function() end\n");
  expectRefused({s, out(), "--script-timeout", "1"}, 1, "mt.lua:12: attempt to index a nil value",
                10);
}

TEST_F(Hostile, BinaryChunksAndOutsideFilesAreRefusedEvenWithEveryGlobalReplaced) {
  const std::string b = write("ld.lua", kEveryGlobalReplaced + "local f = ld('\\27Lua', 'x', 'b')\n"
                                                               "if f then f() end\n");
  const Outcome o = runLray({b, out()}, 10);
  EXPECT_EQ(o.status, 0) << "load returns nil and a message for a binary chunk: " << o.output;
  fs::remove_all(out());
  const std::string f = write("lf.lua", kEveryGlobalReplaced + "local g = dofl('/etc/passwd')\n");
  expectRefused({f, out()}, 1, "lf.lua:10: loadfile: '/etc/passwd'", 10);
  const std::string l =
      write("li.lua", kEveryGlobalReplaced + "for x in lines('/etc/passwd') do end\n");
  expectRefused({l, out()}, 1, "li.lua:10: io.lines: '/etc/passwd'", 10);
  const std::string n = write("ln.lua", kEveryGlobalReplaced + "for x in lines() do end\n");
  expectRefused({n, out()}, 1, "ln.lua:10: io.lines: a file name is required", 10);
}

TEST_F(Hostile, BinaryChunksThroughLoadAreRefused) {
  const std::string s = write("ld.lua", "local f = assert(load('\\27Lua'))" + kScene);
  expectRefused({s, out()}, 1, "ld.lua:1", 10);
}

TEST_F(Hostile, WritingFilesIsRefused) {
  const std::string s = write("w.lua", "local f = io.open('x.txt', 'w')" + kScene);
  expectRefused({s, out()}, 1, "w.lua:1: io.open: only read mode is allowed", 10);
  EXPECT_FALSE(fs::exists(dir_ / "x.txt"));
}

TEST_F(Hostile, OsExecuteIsNotThere) {
  const std::string s = write("os.lua", "os.execute('touch pwned')" + kScene);
  expectRefused({s, out()}, 1, "os.lua:1", 10);
  EXPECT_FALSE(fs::exists(dir_ / "pwned"));
}

TEST_F(Hostile, ASyntaxErrorNamesFileAndLine) {
  const std::string s = write("syn.lua", "local a = 1\nlocal b = = 2" + kScene);
  expectRefused({s, out()}, 1, "syn.lua:2:", 10);
}

TEST_F(Hostile, AWrongTypeNamesTheAttribute) {
  const std::string s = write("ty.lua", "local f = Finish() { diffuse = 'lots' }" + kScene);
  expectRefused({s, out()}, 1, "ty.lua:1: Finish", 10);
}

TEST_F(Hostile, AMisspeltAttributeIsAnError) {
  const std::string s = write("sp.lua", "local f = Finish() { difuse = 1 }" + kScene);
  expectRefused({s, out()}, 1, "did you mean 'diffuse'", 10);
}

TEST_F(Hostile, ASingularTransformIsAnError) {
  const std::string s = write(
      "sg.lua", "function scene()\n  local s = Scene()\n  s:add_entity(Sphere(Scale(0)))\n"
                "  return s\nend\n");
  expectRefused({s, out()}, 1, "sg.lua:3", 10);
}

TEST_F(Hostile, ANonFiniteNumberIsAnError) {
  const std::string s = write("nan.lua", "local v = Vector(0/0, 1, 2)" + kScene);
  expectRefused({s, out()}, 1, "nan.lua:1", 10);
}

TEST_F(Hostile, SceneMustReturnAScene) {
  const std::string s = write("ret.lua", "function scene() return 42 end\n");
  expectRefused({s, out()}, 1, "ret.lua", 10);
}

TEST_F(Hostile, AMissingSceneFileIsOneLine) {
  expectRefused({(dir_ / "none.lua").string(), out()}, 1, "none.lua", 10);
}

TEST_F(Hostile, AFolderGivenAsTheSceneIsRefused) {
  fs::create_directories(dir_ / "scene.lua");
  expectRefused({(dir_ / "scene.lua").string(), out()}, 1, "scene.lua", 10);
}

TEST_F(Hostile, ZeroAndNegativeOptionValuesAreReadable) {
  const std::string s = write("z.lua", kScene);
  for (const char *option :
       {"--threads", "--width", "--samples", "--script-timeout", "--max-pixels"})
    expectRefused({s, out(), option, "0"}, 2, "expects a positive number, got '0'", 10);
  expectRefused({s, out(), "--script-memory", "lots"}, 2,
                "--script-memory: expects a size such as 512M or 4G, got 'lots'", 10);
  expectRefused({s, out(), "--backend", "optix"}, 2, "--backend: unknown value 'optix'", 10);
}

TEST_F(Hostile, AnUnwritableStatsPathLeavesNoTemporaryFile) {
  const std::string s =
      write("st.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
  fs::create_directories(dir_ / "stats.json" / "inside");
  Outcome o = runLray({s, out(), "-q", "--stats", (dir_ / "stats.json").string()}, 10);
  EXPECT_EQ(o.status, 1) << o.output;
  for (const auto &e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST_F(Hostile, ReadingOutsideTheScenesFolderIsRefused) {
  for (const char *call : {"io.open('/etc/passwd')", "io.lines('/etc/passwd')",
                           "dofile('/etc/passwd')", "loadfile('../../../../etc/passwd')",
                           "mesh_from_obj('/etc/passwd')", "ImagePigment2D('/etc/passwd')"}) {
    const std::string s = write("rd.lua", "\nlocal x = " + std::string(call) + kScene);
    expectRefused({s, out()}, 1, "rd.lua:2: ", 10);
    const Outcome o = runLray({s, out()}, 10);
    EXPECT_NE(o.output.find("is outside the folders a scene may read"), std::string::npos)
        << call << ": " << o.output;
  }
}

TEST_F(Hostile, ASymbolicLinkOutOfTheFolderIsRefused) {
  fs::create_symlink("/etc/passwd", dir_ / "innocent.txt");
  const std::string s = write("ln.lua", "local f = io.open('innocent.txt')" + kScene);
  expectRefused({s, out()}, 1, "ln.lua:1: io.open: 'innocent.txt' is outside the folders", 10);
}

TEST_F(Hostile, AllowReadOpensAnotherFolderAndOnlyThat) {
  fs::create_directories(dir_ / "lib");
  std::ofstream(dir_ / "lib" / "colours.lua") << "return 0.5\n";
  fs::create_directories(dir_ / "scene");
  const std::string s = (dir_ / "scene" / "al.lua").string();
  std::ofstream(s) << "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
                      "local v = dofile('../lib/colours.lua')" + kScene;
  expectRefused({s, out()}, 1, "al.lua:2: loadfile: '../lib/colours.lua' is outside", 10);
  const Outcome o = runLray({s, out(), "-q", "--allow-read", (dir_ / "lib").string()}, 10);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::is_regular_file(fs::path(out()) / "al.png"));
  fs::remove_all(out());
  expectRefused({s, out(), "--allow-read", (dir_ / "nothere").string()}, 1,
                "--allow-read: '" + (dir_ / "nothere").string() + "' is not a folder", 10);
}

TEST_F(Hostile, ReadingADeviceOrAFolderWithIoOpenIsRefused) {
  fs::create_directories(dir_ / "sub");
  const std::string s = write("dv.lua", "local f = io.open('sub')" + kScene);
  expectRefused({s, out()}, 1, "dv.lua:1: io.open: 'sub' is not a regular file", 10);
  const std::string z = write("z.lua", "local f = io.open('/dev/zero')" + kScene);
  expectRefused({z, out(), "--allow-read", "/dev"}, 1,
                "z.lua:1: io.open: '/dev/zero' is not a regular file", 10);
}

TEST_F(Hostile, UnsafeLiftsTheConfinement) {
  const std::string s =
      write("us.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
                      "local f = assert(io.open('/etc/passwd'))\nf:close()" +
                          kScene);
  const Outcome o = runLray({s, out(), "-q", "--unsafe"}, 10);
  EXPECT_EQ(o.status, 0) << o.output;
}

TEST_F(Hostile, ARuntimeErrorInALaterFrameLeavesOnlyCompleteEarlierFrames) {
  const std::string s = write(
      "late.lua", "scene_info = SceneInfo() { image_width = 8, image_height = 8, frames = 3 }\n"
                  "function scene(clock)\n  if clock > 0.7 then error('boom') end\n"
                  "  return Scene()\nend\n");
  Outcome o = runLray({s, out(), "-q"}, 10);
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.output.find("late.lua:3: boom"), std::string::npos) << o.output;
  std::vector<std::string> names;
  for (const auto &e : fs::directory_iterator(out())) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"late0000.png", "late0001.png"}));
}

// ---- Numbers and messages: checked in a type that cannot overflow, printed
// readably, bounded and escaped (util/printable_text.h).

TEST_F(Hostile, AnOverflowingSampleCountIsReportedAsItsValue) {
  const std::string s = write("s.lua", kScene);
  const Outcome o = expectRefused({s, out(), "-s", "2147483647"}, 1, "samples^2 = 2.2", 10);
  EXPECT_EQ(o.output.find("= 0 "), std::string::npos) << o.output;
}

TEST_F(Hostile, AHugePixelLimitIsNoLimitNotZero) {
  const std::string s =
      write("p.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
  const Outcome o = runLray({s, out(), "--max-pixels", "1e300", "-q"}, 10);
  EXPECT_EQ(o.status, 0) << o.output;
}

TEST_F(Hostile, AnUninvertibleScaleSaysSoAndNotZero) {
  const std::string s = write("sc.lua", "local t = Scale(1e200)" + kScene);
  const Outcome o = expectRefused({s, out()}, 1, "sc.lua:1: Scale(1e+200, 1e+200, 1e+200): the "
                                                 "factors are too large or too small", 10);
  EXPECT_EQ(o.output.find("is zero"), std::string::npos) << o.output;
}

TEST_F(Hostile, HugeNumbersInAWarningArePrintedShort) {
  const std::string s = write(
      "w.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
               "function scene() return Scene() { camera = Perspective(45, 1e300) } end\n");
  const Outcome o = runLray({s, out(), "-q"}, 10);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("camera aspect 1e+300 differs"), std::string::npos) << o.output;
  EXPECT_LT(o.output.size(), 300u) << o.output;
}

TEST_F(Hostile, ExtremeClocksGiveEveryFrameAFiniteClock) {
  const std::string s = write(
      "c.lua", "scene_info = SceneInfo() { image_width = 2, image_height = 2, frames = 3,\n"
               "  start_clock = -1e308, end_clock = 1e308 }\n"
               "function scene(clock)\n"
               "  if clock ~= clock or clock == math.huge or clock == -math.huge then\n"
               "    error('clock ' .. tostring(clock))\n"
               "  end\n"
               "  return Scene()\n"
               "end\n");
  const Outcome o = runLray({s, out(), "-q"}, 10);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::is_regular_file(fs::path(out()) / "c0001.png"));
}

TEST_F(Hostile, AHugeErrorMessageIsCutShort) {
  const std::string s = write("big.lua", "error(string.rep('x', 10 * 1024 * 1024))" + kScene);
  const Outcome o = expectRefused({s, out()}, 1, "big.lua:1: xxxx", 20);
  EXPECT_LT(o.output.size(), 8192u);
  EXPECT_NE(o.output.find("more bytes left out"), std::string::npos);
}

TEST_F(Hostile, EscapeSequencesAndInvalidUtf8NeverReachTheTerminal) {
  const std::string s =
      write("esc.lua", "error('\\27[2J\\27]0;pwned\\7 \\255\\194\\155 ok \\u{e9}')" + kScene);
  const Outcome o = expectRefused(
      {s, out()}, 1, "esc.lua:1: \\x1b[2J\\x1b]0;pwned\\x07 \\xff\\u009b ok \xc3\xa9", 10);
  EXPECT_EQ(o.output.find('\x1b'), std::string::npos);
  EXPECT_EQ(o.output.find('\x07'), std::string::npos);
  // A path with them, named in a message, is escaped the same way.
  const Outcome p = expectRefused({(dir_ / "no\x1b[31mpe\xff.lua").string(), out()}, 1,
                                  "no\\x1b[31mpe\\xff.lua", 10);
  EXPECT_EQ(p.output.find('\x1b'), std::string::npos);
}

// ---- Output that never lies: a complete file or none, every error with its
// path and reason, and what is not a regular file written to, never replaced.

const std::string kNoisy =
    "scene_info = SceneInfo() { image_width = 64, image_height = 64 }\n"
    "function scene()\n"
    "  local s = Scene() { camera = Perspective(45, 1) { transform = Translate(-4*z) } }\n"
    "  s:add_entity(Sphere() { texture = Texture() { pigment = MarblePigment3D() } })\n"
    "  s:add_light(Light() { transform = Translate(Vector(-3, 3, -3)) })\n"
    "  return s\n"
    "end\n";

TEST_F(Hostile, AFileSizeLimitLeavesNoPartialImage) {
  const std::string s = write("fs.lua", kNoisy);
  for (const char *format : {"tga", "png", "exr"}) {
    SCOPED_TRACE(format);
    const Outcome o = runLray({s, out(), "-q", "-f", format, "-w", "200", "-H", "200"}, 20, 2048);
    EXPECT_EQ(o.status, 1) << o.output;
    EXPECT_NE(o.output.find("cannot write image '" + out() + "/fs." + format + "': "),
              std::string::npos)
        << o.output;
    EXPECT_EQ(o.output.find("internal error"), std::string::npos) << o.output;
    for (const auto &e : fs::directory_iterator(out())) ADD_FAILURE() << "left " << e.path();
  }
}

TEST_F(Hostile, AnImageThroughALinkToADeviceIsWrittenThroughNotReplaced) {
  const std::string s = write("dev.lua", kNoisy);
  fs::create_directories(out());
  const fs::path link = fs::path(out()) / "dev.png";
  fs::create_symlink("/dev/full", link);
  const Outcome o = runLray({s, out(), "-q"}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("cannot write image '" + link.string() + "': No space left on device"),
            std::string::npos)
      << o.output;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), "/dev/full");
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST_F(Hostile, StatsThroughALinkToDevNullLeaveTheDeviceAlone) {
  const std::string s =
      write("st.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
  const fs::path link = dir_ / "stats.json";
  fs::create_symlink("/dev/null", link);
  const Outcome o = runLray({s, out(), "-q", "--stats", link.string()}, 20);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), "/dev/null");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // Into a full device: the reason, and exit 1.
  const Outcome full = runLray({s, out(), "-q", "--stats", "/dev/full"}, 20);
  EXPECT_EQ(full.status, 1) << full.output;
  EXPECT_NE(full.output.find("cannot write statistics '/dev/full': No space left on device"),
            std::string::npos)
      << full.output;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST_F(Hostile, StatsThroughALinkToAFileReplaceTheFileAndKeepTheLink) {
  const std::string s =
      write("sl.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
  write("real.json", "old");
  const fs::path link = dir_ / "stats.json";
  fs::create_symlink(dir_ / "real.json", link);
  const Outcome o = runLray({s, out(), "-q", "--stats", link.string()}, 20);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::is_symlink(link));
  std::ifstream in(dir_ / "real.json");
  const std::string json{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_NE(json.find("\"lray_version\""), std::string::npos) << json;
}

TEST_F(Hostile, AFolderInTheWayOfAnImageIsNamed) {
  const std::string s =
      write("fo.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
  fs::create_directories(fs::path(out()) / "fo.png" / "inside");
  const Outcome o = runLray({s, out(), "-q"}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("cannot write image '" + out() + "/fo.png': a folder of that name is "
                          "in the way"),
            std::string::npos)
      << o.output;
  EXPECT_EQ(o.output.find("internal error"), std::string::npos) << o.output;
}

// ---- lray-merge on crafted tiles: headers checked before anything is
// allocated, every good set merged, every bad tile named, messages bounded.

/// An EXR tile as lray writes them, but with whatever header it is given.
void writeCraftedTile(const fs::path &path, int fullWidth, int fullHeight, int x0, int y0,
                      int width, int height, int channels, const std::string &finalName,
                      const std::string &format = "png") {
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
  spec.x = x0;
  spec.y = y0;
  spec.full_width = fullWidth;
  spec.full_height = fullHeight;
  const char *names[] = {"R", "G", "B", "Error", "SampleCount"};
  spec.channelnames.clear();
  for (int c = 0; c < channels; ++c)
    spec.channelnames.push_back(c < 5 ? names[c] : "X" + std::to_string(c));
  spec.attribute("lray:final", finalName);
  spec.attribute("lray:format", format);
  spec.attribute("lray:encoding", "linear");
  spec.attribute("lray:render", "0123456789abcdef");
  spec.attribute("compression", "zip");
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec));
  std::vector<float> pixels(static_cast<size_t>(width) * height * channels, 0.5f);
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  out->close();
}

TEST_F(Hostile, ATileClaimingAHugeFrameIsRefusedBeforeAllocating) {
  fs::create_directories(out());
  writeCraftedTile(fs::path(out()) / "big.tile-0-of-1.exr", 16384, 16384, 0, 0, 1, 1, 5, "big.png");
  const Outcome o = runMerge({out()}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("big.png: its tiles hold 1 pixels of its 16384 x 16384"),
            std::string::npos)
      << o.output;
  EXPECT_LT(o.peakKiB, 200 * 1024) << "peak memory";
  EXPECT_FALSE(fs::exists(fs::path(out()) / "big.png"));
}

/// Overwrites the bytes after `key` (an attribute's name and type, NULs
/// included) in an EXR's header: the attribute's size, then its value.
void patchExrHeader(const fs::path &path, const std::string &key,
                    const std::vector<int32_t> &ints) {
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  std::memcpy(&bytes[at + key.size()], ints.data(), 4 * ints.size()); // little-endian, as EXR
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST_F(Hostile, ATileHeaderClaimingMoreThanItsBytesIsRefusedBeforeOpenExrReadsIt) {
  // Tiles of 1 KiB whose header claims 16384 x 16384 pixels of 12
  // channels (12 GiB as floats), or an attribute of 1.8 GB (found by the
  // merge_tile fuzz target: lray-merge grew to 1.9 GiB in OpenEXR's reader).
  const std::string data("dataWindow\0box2i\0", 17), name("lray:final\0string\0", 18);
  struct Case {
    std::string key;
    std::vector<int32_t> ints;
    std::string message;
  };
  for (const Case &c : {Case{data, {16, 0, 0, 16383, 16383},
                             "its header claims 16384 x 16384 pixels, more than its"},
                        Case{name, {1887007752}, "its header is cut short or malformed"}}) {
    SCOPED_TRACE(c.message);
    fs::remove_all(out());
    fs::create_directories(out());
    const fs::path tile = fs::path(out()) / "big.tile-0-of-1.exr";
    writeCraftedTile(tile, 16384, 16384, 0, 0, 1, 1, 12, "big.png");
    patchExrHeader(tile, c.key, c.ints);
    const Outcome o = runMerge({out()}, 20);
    EXPECT_FALSE(o.timedOut);
    EXPECT_EQ(o.status, 1) << o.output;
    EXPECT_NE(o.output.find("big.tile-0-of-1.exr': " + c.message), std::string::npos) << o.output;
    EXPECT_LT(o.peakKiB, 200 * 1024) << "peak memory";
    EXPECT_FALSE(fs::exists(fs::path(out()) / "big.png"));
  }
}

TEST_F(Hostile, OneBadTileLeavesTheGoodSetsToMergeAndIsNamed) {
  const std::string s =
      write("good.lua", "scene_info = SceneInfo() { image_width = 8, image_height = 40 }" + kScene);
  ASSERT_EQ(runLray({s, out(), "-q", "--tile", "0/2"}, 20).status, 0);
  ASSERT_EQ(runLray({s, out(), "-q", "--tile", "1/2"}, 20).status, 0);
  writeCraftedTile(fs::path(out()) / "bad.tile-0-of-1.exr", 8, 8, 0, 0, 8, 8, 16, "bad.png");
  const Outcome o = runMerge({out()}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("bad.tile-0-of-1.exr': 16 channels, more than an LRay tile has"),
            std::string::npos)
      << o.output;
  EXPECT_TRUE(fs::is_regular_file(fs::path(out()) / "good.png")) << o.output;
}

TEST_F(Hostile, AnAbsurdTileCountGivesAShortMessage) {
  fs::create_directories(out());
  writeCraftedTile(fs::path(out()) / "a.tile-0-of-999999.exr", 8, 8, 0, 0, 8, 8, 5, "a.png");
  const Outcome o = runMerge({out()}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("and 999993 more"), std::string::npos) << o.output.substr(0, 500);
  EXPECT_LT(o.output.size(), 4096u);
}

TEST_F(Hostile, ATileNamingItselfAsItsFrameIsRefusedAndKept) {
  fs::create_directories(out());
  const fs::path tile = fs::path(out()) / "t.tile-0-of-1.exr";
  writeCraftedTile(tile, 8, 8, 0, 0, 8, 8, 5, "t.tile-0-of-1.exr", "exr");
  const Outcome o = runMerge({out()}, 20);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("which is not its own"), std::string::npos) << o.output;
  EXPECT_TRUE(fs::is_regular_file(tile));
}

TEST_F(Hostile, TilesOfScenesNamedWithADotOrANewlineMerge) {
  for (const std::string name : {".dot", "new\nline"}) {
    SCOPED_TRACE(name);
    const std::string s = write(
        name + ".lua", "scene_info = SceneInfo() { image_width = 8, image_height = 40 }" + kScene);
    const std::string folder = (dir_ / ("out" + std::to_string(name.size()))).string();
    ASSERT_EQ(runLray({s, folder, "-q", "--tile", "0/2"}, 20).status, 0);
    ASSERT_EQ(runLray({s, folder, "-q", "--tile", "1/2"}, 20).status, 0);
    const Outcome o = runMerge({folder}, 20);
    EXPECT_EQ(o.status, 0) << o.output;
    EXPECT_TRUE(fs::is_regular_file(fs::path(folder) / (name + ".png"))) << o.output;
  }
}

// ---- Out of memory anywhere: one clear message and exit 1, in bounded time,
// whatever the address-space limit (ulimit -v) lets LRay get to.

TEST_F(Hostile, AnAddressSpaceLimitIsOneClearMessageWherEverItBites) {
  const std::string s = write("as.lua", kNoisy);
  // 60 MiB: TBB cannot start its worker threads (their stacks do not fit)
  // while the scene loads; below about 48 the dynamic loader itself fails.
  for (rlim_t mib : {60, 64, 200, 440, 500, 600, 800}) {
    SCOPED_TRACE(std::to_string(mib) + " MiB");
    fs::remove_all(out());
    const Outcome o = runProgram(LRAY_BINARY, {s, out(), "-q", "-f", "exr"}, 60, RLIM_INFINITY,
                                 mib << 20);
    EXPECT_FALSE(o.timedOut);
    ASSERT_TRUE(o.status == 0 || o.status == 1) << "killed or aborted: " << o.output;
    if (o.status == 0) continue; // it fitted
    EXPECT_EQ(o.output.rfind("lray: error: ", 0), 0u) << o.output;
    EXPECT_NE(o.output.find("memory"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("internal error"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("terminate called"), std::string::npos) << o.output;
    if (fs::exists(out()))
      for (const auto &e : fs::directory_iterator(out())) ADD_FAILURE() << "left " << e.path();
  }
}

// ---- --render-memory: the frame's model, textures and acceleration structure ----

/// 4096 solids in one Intersection (the limit of one tree), listed 2^20
/// times through shared Unions: four billion leaves.
const std::string kCopiedSubtree =
    "local u = Intersection { Sphere(), Sphere() }\n"
    "for i = 1, 11 do u = Intersection { u, u } end\n"
    "for i = 1, 20 do u = Union { u, u } end\n"
    "function scene()\n  local s = Scene()\n  s:add_entity(u)\n  return s\nend\n";

/// Refused at a line of the copied subtree: a leaf's or a node's (which
/// passes the budget first depends on the length of the path and the size
/// of a leaf).
void expectAtTheCopiedSubtree(const std::string &output) {
  EXPECT_TRUE(output.find("dag.lua:1: Sphere: ") != std::string::npos ||
              output.find("dag.lua:1: Intersection: ") != std::string::npos ||
              output.find("dag.lua:2: Intersection: ") != std::string::npos)
      << output;
}

TEST_F(Hostile, ASubtreeListedManyTimesIsChargedEachTimeItIsCopied) {
  // Refused at a leaf, long before four billion of them are made.
  const std::string s = write("dag.lua", kCopiedSubtree);
  const Outcome o =
      expectRefused({s, out(), "--render-memory", "256M"}, 1,
                    ": the frame would need more than the render memory budget of 256 MiB (raise "
                    "it with --render-memory)",
                    30, 700);
  expectAtTheCopiedSubtree(o.output);
}

TEST_F(Hostile, TheDefaultRenderBudgetFollowsTheProcesssMemoryLimit) {
  // Under a 3 GiB address space (ulimit -v, as a farm would set) and no
  // --render-memory, the copied subtree is refused at its line by the
  // budget, not by an allocation failing somewhere inside.
  const std::string s = write("dag.lua", kCopiedSubtree);
  const Outcome o = runProgram(LRAY_BINARY, {s, out()}, 60, RLIM_INFINITY, rlim_t{3} << 30);
  EXPECT_FALSE(o.timedOut);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find(": the frame would need more than the render memory budget of 1.5 "
                          "GiB (raise it with --render-memory)"),
            std::string::npos)
      << o.output;
  expectAtTheCopiedSubtree(o.output);
}

TEST_F(Hostile, OneEntityAddedMillionsOfTimesIsRefusedAtItsLine) {
  const std::string s = write("many.lua",
                              "local b = Sphere()\nfunction scene()\n  local s = Scene()\n"
                              "  for i = 1, 3000000 do s:add_entity(b) end\n  return s\nend\n");
  expectRefused({s, out(), "--render-memory", "128M"}, 1,
                "many.lua:1: Sphere: the frame would need more than the render memory budget of "
                "128 MiB",
                60, 700);
}

TEST_F(Hostile, TexturesAreChargedByTheirBytesSummed) {
  // Two 2000 x 2000 TGA images, 60 MB each decoded (bytes and floats kept):
  // each fits the budget alone, the two together do not.
  std::string tga(18, '\0');
  tga[2] = 2;                                   // uncompressed true colour
  tga[12] = char(2000 & 255), tga[13] = char(2000 >> 8);
  tga[14] = char(2000 & 255), tga[15] = char(2000 >> 8);
  tga[16] = 24;
  tga += std::string(size_t{2000} * 2000 * 3, '\x40');
  write("a.tga", tga);
  write("b.tga", tga);
  const std::string head = "function scene()\n  local s = Scene()\n";
  const std::string one =
      "  s:add_entity(Sphere() { texture = Texture() { pigment = ImagePigment2D('a.tga') } })\n";
  const std::string two =
      "  s:add_entity(Sphere() { texture = Texture() { pigment = ImagePigment2D('b.tga') } })\n";
  const std::string tail = "  return s\nend\n";
  const std::string alone = write("alone.lua", head + one + tail);
  const Outcome fits = runLray({alone, out(), "-q", "-w", "4", "-H", "4", "--render-memory",
                                "100M"}, 30);
  EXPECT_EQ(fits.status, 0) << fits.output;
  fs::remove_all(out());
  const std::string both = write("both.lua", head + one + two + tail);
  expectRefused({both, out(), "-w", "4", "-H", "4", "--render-memory", "100M"}, 1,
                "both.lua:4: ImagePigment2D: image '", 30, 400);
  expectRefused({both, out(), "-w", "4", "-H", "4", "--render-memory", "100M"}, 1,
                "b.tga': the frame would need more than the render memory budget of 100 MiB "
                "(raise it with --render-memory)",
                30, 400);
}

TEST_F(Hostile, TheAccelerationStructureIsChargedBeforeItIsBuilt) {
  // 300,000 spheres: the model (about 400 bytes each) fits in 200 MiB, the
  // model and the backend's build together do not, on either backend.
  const std::string s = write(
      "accel.lua", "function scene()\n  local s = Scene()\n  for i = 1, 300000 do\n"
                   "    s:add_entity(Sphere(Translate(Vector(i, 0, 0))))\n  end\n"
                   "  return s\nend\n");
  for (const char *backend : {"embree", "kdtree"}) {
    SCOPED_TRACE(backend);
    expectRefused({s, out(), "-w", "4", "-H", "4", "--backend", backend, "--render-memory",
                   "200M"},
                  1,
                  "accel.lua:4: the acceleration structure of 300000 entities and 0 triangles: "
                  "the frame would need more than the render memory budget of 200 MiB",
                  60, 700);
  }
}

TEST_F(Hostile, AnObjIsChargedAsItIsParsedNotAfter) {
  // 40 MB of vertices: the text fits in 64 MiB, the text and the arrays do not.
  std::string obj;
  obj.reserve(40u << 20);
  while (obj.size() < (40u << 20)) obj += "v 1 2 3\n";
  write("big.obj", obj);
  const std::string s = write("obj.lua", "\nlocal m = mesh_from_obj('big.obj')" + kScene);
  expectRefused({s, out(), "--script-memory", "64M"}, 1,
                "obj.lua:2: mesh_from_obj: big.obj:", 30, 250);
  expectRefused({s, out(), "--script-memory", "64M"}, 1,
                "MiB the script has left of its memory (raise it with --script-memory)", 30, 250);
  // Larger than all the script has left: refused before it is read.
  const Outcome o = runLray({s, out(), "--script-memory", "32M"}, 30);
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.output.find("obj.lua:2: mesh_from_obj: big.obj: 41943040 bytes, more than"),
            std::string::npos)
      << o.output;
  EXPECT_LT(o.peakKiB, 150 * 1024);
}

TEST_F(Hostile, SkipExistingNeverDecodesAnExistingImageOfAnotherSize) {
  // An existing "frame" whose header claims 100000 x 100000 texels: read as
  // a header only, found to be of another size, and rendered over.
  const std::string png = hugePngHeader() + std::string(1 << 20, '\0');
  const std::string s = write("skip.lua", kScene);
  fs::create_directories(out());
  std::ofstream(fs::path(out()) / "skip.png", std::ios::binary) << png;
  const Outcome o = runLray({s, out(), "-q", "-w", "8", "-H", "8", "--skip-existing"}, 20);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_LT(o.peakKiB, 200 * 1024);
  EXPECT_LT(fs::file_size(fs::path(out()) / "skip.png"), 1000u) << "not rendered over";
}

} // namespace
} // namespace lray
