// Unit tests: bindings/lua_allocator (the lua_Alloc behind every script state).
#include "bindings/lua_allocator.h"
#include "bindings/scene_script.h"
#include "bindings/script_state.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace lray::lua {
namespace {

void *alloc(LuaAllocator &a, void *p, size_t oldSize, size_t newSize) {
  return LuaAllocator::allocate(&a, p, oldSize, newSize);
}

// Enough small blocks to fill the small first slab and several 2 MiB ones:
// every block stays writable, distinct and 16-byte aligned, and the bytes
// in use are counted exactly.
TEST(LuaAllocator, SmallBlocksAcrossSlabsStayDistinctAndCounted) {
  LuaAllocator a;
  std::vector<std::pair<unsigned char *, size_t>> blocks;
  size_t expected = 0;
  for (size_t i = 0; i < 40000; ++i) {
    size_t size = 1 + (i * 37) % 512;
    auto *p = static_cast<unsigned char *>(alloc(a, nullptr, 0, size));
    ASSERT_NE(p, nullptr);
    ASSERT_EQ(reinterpret_cast<uintptr_t>(p) % 16, 0u);
    std::memset(p, static_cast<int>(i & 0xFF), size);
    blocks.emplace_back(p, size);
    expected += size;
  }
  EXPECT_EQ(a.bytesInUse(), expected);
  for (size_t i = 0; i < blocks.size(); ++i) {
    auto [p, size] = blocks[i];
    ASSERT_EQ(p[0], static_cast<unsigned char>(i & 0xFF)) << i;
    ASSERT_EQ(p[size - 1], static_cast<unsigned char>(i & 0xFF)) << i;
  }
  for (auto [p, size] : blocks) alloc(a, p, size, 0);
  EXPECT_EQ(a.bytesInUse(), 0u);
}

TEST(LuaAllocator, FreedBlocksAreReusedAndReallocKeepsContents) {
  LuaAllocator a;
  void *p = alloc(a, nullptr, 0, 40);
  alloc(a, p, 40, 0);
  void *q = alloc(a, nullptr, 0, 48); // same 48-byte class: the freed block
  EXPECT_EQ(p, q);
  std::memcpy(q, "0123456789", 10);
  void *big = alloc(a, q, 48, 100000); // small -> large
  ASSERT_NE(big, nullptr);
  EXPECT_EQ(std::memcmp(big, "0123456789", 10), 0);
  void *back = alloc(a, big, 100000, 16); // large -> small
  EXPECT_EQ(std::memcmp(back, "0123456789", 10), 0);
  EXPECT_EQ(a.bytesInUse(), 16u);
  alloc(a, back, 16, 0);
  EXPECT_EQ(a.bytesInUse(), 0u);
}

// A request near SIZE_MAX is refused by the limit, not wrapped around it
// into malloc.
TEST(LuaAllocator, HugeRequestsAreRefusedByTheLimitWithoutWrapping) {
  LuaAllocator a;
  a.setLimit(size_t{1} << 20);
  void *p = alloc(a, nullptr, 0, 64);
  ASSERT_NE(p, nullptr);
  a.takeRefused();
  for (size_t huge : {SIZE_MAX, SIZE_MAX - 8, SIZE_MAX - 64, SIZE_MAX / 2 + 1}) {
    EXPECT_EQ(alloc(a, nullptr, 0, huge), nullptr) << huge;
    EXPECT_TRUE(a.takeRefused()) << huge;
    EXPECT_EQ(alloc(a, p, 64, huge), nullptr) << huge;
    EXPECT_TRUE(a.takeRefused()) << huge;
  }
  EXPECT_EQ(a.bytesInUse(), 64u);
  alloc(a, p, 64, 0);
}

} // namespace
} // namespace lray::lua

namespace lray {
namespace {

// A script stopped at its memory limit still has its objects' finalizers
// run when its state closes (they free the C++ parts: a Mesh's arrays,
// a CSG node's list). The ASan build (scripts/test) reports a leak if not.
TEST(ScriptMemoryLimit, ObjectsOfAStoppedScriptAreStillFreed) {
  for (const char *exhaust : {"local t = {} for i = 1, 1e9 do t[i] = ('x'):rep(100) .. i end",
                              "local function r(n) return 1 + r(n + 1) end r(1)"}) {
    ScriptOptions options;
    options.memoryLimitBytes = uint64_t{256} << 10; // tight: the close has no room left
    const std::string source =
        "keep = {}\n"
        "for i = 1, 20 do keep[i] = Mesh() { vertices = { {0, 0, 0}, {1, 0, 0}, {0, 1, 0} } } end\n"
        "for i = 1, 20 do keep[20 + i] = Union { Sphere(), Cube() } end\n"
        "pcall(function() return Mesh { vertices = keep } end)\n" // garbage with a finalizer
        "pcall(function() return Mesh { vertices = keep } end)\n" +
        std::string(exhaust) + "\n";
    EXPECT_THROW(SceneScript::fromString(source, "limit.lua", ".", options), SceneError) << exhaust;
  }
}

// Every C++ object a script made is destroyed with its state, whatever
// stopped the script: objects are charged to the script's external memory
// pool while they live, so the pool must read zero afterwards.
TEST(ScriptMemoryLimit, EveryObjectIsDestroyedWithItsStateWhateverStoppedTheScript) {
  const std::string exhausted =
      "keep = {} for i = 1, 50 do keep[i] = Union { Sphere(), Cube() } end\n"
      "local t = {} for i = 1, 1e9 do t[i] = ('x'):rep(100) .. i end\n";
  const std::string finished = "keep = {} for i = 1, 50 do keep[i] = Mesh() end\n";
  for (const std::string *source : {&exhausted, &finished}) {
    ScriptOptions options;
    options.memoryLimitBytes = uint64_t{256} << 10;
    std::shared_ptr<lua::ExternalMemory> pool;
    {
      lua::ScriptState state(".", options);
      pool = state.context().allocator->external();
      if (source == &finished) {
        state.run(*source, "@limit.lua");
        EXPECT_GT(pool->bytes.load(), 0u) << "live objects are charged";
      } else {
        EXPECT_THROW(state.run(*source, "@limit.lua"), SceneError);
      }
    }
    EXPECT_EQ(pool->bytes.load(), 0u) << *source;
  }
}

// When a finalizer call itself fails for lack of memory, Lua frees the
// userdata without calling it ("error in __gc" warning). Its C++ object
// must still be freed with the state, and nothing may read the freed
// userdata (the ASan build runs this test too). Which limits make the
// finalizer calls fail depends on the heap's layout, so a range is swept
// and at least one must have.
TEST(ScriptMemoryLimit, ObjectsWhoseFinalizerCallFailedAreStillFreed) {
  const std::string source =
      "for round = 1, 20 do pcall(function() for i = 1, 300 do local m = Mesh() end\n"
      "  local function f(n) return 1 + f(n + 1) end return f(1) end) end\n";
  int failedFinalizers = 0;
  for (uint64_t kib = 128; kib <= 320; kib += 8) {
    ScriptOptions options;
    options.memoryLimitBytes = kib << 10;
    std::shared_ptr<lua::ExternalMemory> pool;
    {
      lua::ScriptState state(".", options);
      pool = state.context().allocator->external();
      lua_setwarnf(
          state.state(),
          +[](void *count, const char *message, int) {
            if (std::strstr(message, "__gc")) ++*static_cast<int *>(count);
          },
          &failedFinalizers);
      try {
        state.run(source, "@finalizers.lua");
      } catch (const SceneError &) {
      }
    }
    EXPECT_EQ(pool->bytes.load(), 0u) << kib << " KiB";
  }
  EXPECT_GT(failedFinalizers, 0) << "no limit made a finalizer call fail: widen the sweep";
}

// A limit below what LRay's own libraries take is a clean error naming the
// flag (it once aborted while the libraries were opened).
TEST(ScriptMemoryLimit, ALimitBelowTheLibrariesIsACleanError) {
  for (uint64_t limit : {uint64_t{1}, uint64_t{1} << 10, uint64_t{16} << 10}) {
    ScriptOptions options;
    options.memoryLimitBytes = limit;
    try {
      SceneScript::fromString("return 1\n", "tiny.lua", ".", options);
      ADD_FAILURE() << limit;
    } catch (const SceneError &e) {
      EXPECT_NE(std::string(e.what()).find("--script-memory"), std::string::npos) << e.what();
    }
  }
}

} // namespace
} // namespace lray
