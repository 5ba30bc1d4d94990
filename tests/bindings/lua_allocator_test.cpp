// Unit tests: bindings/lua_allocator (the lua_Alloc behind every script state).
#include "bindings/lua_allocator.h"
#include "bindings/scene_script.h"

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

} // namespace
} // namespace lray
