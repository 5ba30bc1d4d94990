// Tests for src/shading/shadow_batch: a batch made for a thread's first
// tile writes nothing into its ray arrays (most of its megabyte), so a
// light of few rounds touches only the pages it uses.
#include "shading/shadow_batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <new>

namespace lray {
namespace {

bool allBytes(const void *p, size_t n, unsigned char v) {
  const auto *b = static_cast<const unsigned char *>(p);
  return std::all_of(b, b + n, [v](unsigned char x) { return x == v; });
}

TEST(ShadowBatch, MakingOneLeavesItsRayArraysUnwritten) {
  constexpr unsigned char kMark = 0xA5;
  auto storage = std::make_unique<std::byte[]>(sizeof(ShadowBatch) + alignof(ShadowBatch));
  void *raw = storage.get();
  size_t space = sizeof(ShadowBatch) + alignof(ShadowBatch);
  void *at = std::align(alignof(ShadowBatch), sizeof(ShadowBatch), raw, space);
  ASSERT_NE(at, nullptr);
  std::fill_n(static_cast<unsigned char *>(at), sizeof(ShadowBatch), kMark);
  auto *batch = new (at) ShadowBatch; // as TileScratch makes it
  EXPECT_EQ(batch->rounds, 0u);
  EXPECT_EQ(batch->count, 0u);
  EXPECT_TRUE(allBytes(batch->rays, sizeof batch->rays, kMark));
  EXPECT_TRUE(allBytes(batch->sorted, sizeof batch->sorted, kMark));
  batch->~ShadowBatch();
}

} // namespace
} // namespace lray
