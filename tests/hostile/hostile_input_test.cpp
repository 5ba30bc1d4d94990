// The hostile-input suite (CTest label "hostile"): scene files and command
// lines a careless or hostile author could hand a render farm, each run as
// a real `lray` process. Every case asserts that the process ends within a
// bound, its exit status, one readable message naming the file and line
// (or the path or value), its peak memory, and that the output folder
// holds nothing but complete images.
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

/// Runs lray with `args`, killing it after `limitSeconds`.
Outcome runLray(const std::vector<std::string> &args, double limitSeconds) {
  int pipeFds[2];
  if (pipe(pipeFds) != 0) return {};
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = fork();
  if (pid == 0) {
    dup2(pipeFds[1], 1);
    dup2(pipeFds[1], 2);
    close(pipeFds[0]);
    close(pipeFds[1]);
    std::vector<char *> argv{const_cast<char *>(LRAY_BINARY)};
    for (const std::string &a : args) argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    execv(LRAY_BINARY, argv.data());
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
      write("mem.lua", "local t = {}\nfor i = 1, 1e9 do\n  t[i] = string.rep('x', 1000) .. i\nend" + kScene);
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
  const Outcome o = expectRefused({s, out(), "--script-memory", "256M"}, 1, "meshes.lua:6: ", 60, 600);
  EXPECT_NE(o.output.find("the script needed more than 256 MiB of memory"), std::string::npos)
      << o.output;
}

TEST_F(Hostile, AMeshRebuiltEveryFrameDoesNotAccumulateCharges) {
  // Meshes dropped by the script are uncharged when collected.
  const std::string s = write(
      "anim.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4, frames = 10 }\n"
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
  const Outcome o = expectRefused({s, out(), "--script-memory", "64M"}, 1, "chunks.lua:4: done", 60, 150);
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
                                               "setmetatable(_G, {__index = " + std::string(index) + "})\n");
    const Outcome o = runLray({s, out(), "-q", "-w", "4", "-H", "4", "--script-timeout", "2"}, 20);
    EXPECT_FALSE(o.timedOut) << index;
    EXPECT_EQ(o.status, 0) << index << ": " << o.output;
  }
}

// With --unsafe a finalizer can run in lua_close after LRay freed its
// objects' C++ parts: an LRay object it still holds reads as no object
// (scripts/test runs this with the ASan lray too).
TEST_F(Hostile, AnUnsafeFinalizerNeverSeesAFreedObject) {
  const std::string s = write(
      "late.lua", "local m = Mesh() { vertices = { {0, 0, 0}, {1, 0, 0}, {0, 1, 0} } }\n"
                  "keep = setmetatable({}, {__gc = function() local ok = pcall(function() return m.smooth end)\n"
                  "  io.write(ok and 'read' or 'refused', '\\n') end})\n" + kScene.substr(1));
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
  const std::string s = write("grow.lua", "local t = {}\nfor i = 1, 1e9 do t[i] = ('y'):rep(4096) .. i end" + kScene);
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
  const std::string s = write("gc.lua",
                              "setmetatable({}, { __gc = function() while true do end end })" + kScene);
  expectRefused({s, out(), "--script-timeout", "1"}, 1,
                "gc.lua:1: setmetatable: __gc finalizers are not allowed in scene scripts", 10);
}

TEST_F(Hostile, AFinalizerAddedAfterSetmetatableNeverRuns) {
  // Lua marks an object for finalization only at setmetatable: adding
  // __gc later is inert, and the render completes.
  const std::string s = write(
      "late.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
                  "local mt = {}\nsetmetatable({}, mt)\nmt.__gc = function() while true do end end\n"
                  "collectgarbage()" + kScene);
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
  expectRefused({s, out(), "--script-timeout", "1"}, 1, "swap.lua:3: attempt to index a nil value", 10);
  const std::string t = write(
      "swap2.lua", "local mt = getmetatable(Sphere())\n"
                   "mt.__gc = function() while true do end end" + kScene);
  expectRefused({t, out(), "--script-timeout", "1"}, 1, "swap2.lua:2: attempt to index a nil value", 10);
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
    const std::string s = write(
        "csg.lua", std::string("local u = Sphere()\nfor i = 1, 100000 do\n  u = ") + op +
                       " { u, Cube() }\nend\n"
                       "function scene()\n  local s = Scene()\n  s:add_entity(u)\n  return s\nend\n");
    expectRefused({s, out()}, 1, "csg.lua:3: " + std::string(op) + ": CSG nodes are nested more than 64 deep", 20);
  }
}

TEST_F(Hostile, ASharedUnionThatDoublesFortyTimesIsRefused) {
  const std::string s = write(
      "double.lua", "local u = Sphere()\nfor i = 1, 40 do u = Union { u, u } end\n"
                    "function scene()\n  local s = Scene()\n  s:add_entity(u)\n  return s\nend\n");
  expectRefused({s, out()}, 1, "double.lua:2: Union: expands to more than 2097152 solids", 30, 1500);
}

TEST_F(Hostile, AHugeCsgTreeIsRefusedNamingTheLine) {
  const std::string s = write(
      "big.lua", "local list = {}\nfor i = 1, 200000 do list[i] = Sphere() end\n"
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
  expectRefused({s, out(), "--max-file-size", "4K"}, 1,
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
  // A valid signature and IHDR chunk for 100000 x 100000 RGB, and no data.
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
  write("huge.png", png);
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
  for (const char *option : {"--threads", "--width", "--samples", "--script-timeout", "--max-pixels"})
    expectRefused({s, out(), option, "0"}, 2, "expects a positive number, got '0'", 10);
  expectRefused({s, out(), "--script-memory", "lots"}, 2,
                "--script-memory: expects a size such as 512M or 4G, got 'lots'", 10);
  expectRefused({s, out(), "--backend", "optix"}, 2, "--backend: unknown value 'optix'", 10);
}

TEST_F(Hostile, AnUnwritableStatsPathLeavesNoTemporaryFile) {
  const std::string s = write("st.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }" + kScene);
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
  expectRefused({z, out(), "--allow-read", "/dev"}, 1, "z.lua:1: io.open: '/dev/zero' is not a regular file", 10);
}

TEST_F(Hostile, UnsafeLiftsTheConfinement) {
  const std::string s = write("us.lua", "scene_info = SceneInfo() { image_width = 4, image_height = 4 }\n"
                                        "local f = assert(io.open('/etc/passwd'))\nf:close()" + kScene);
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

} // namespace
} // namespace lray
