// Tests for src/accel/kdtree/triangle_prefilter.h: the float prefilter never
// rejects a triangle the exact watertight test hits, also for rays through
// vertices and edges and far from the origin, and rejects clear misses; its
// AVX2 version (triangle_prefilter_avx2.cpp) agrees lane by lane.
#include "accel/kdtree/triangle_prefilter.h"
#include "accel/kdtree/kdtree_test_util.h"
#include "util/cpu_features.h"

#include <gtest/gtest.h>

#include <bit>
#include <limits>

namespace lray {
namespace {

using kdtest::Rng;

Vec3f toFloat(const Vec3 &v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}
Vec3 toDouble(const Vec3f &v) { return {v.x, v.y, v.z}; }

template <int Kz> uint32_t packetPass(const PrefilterRay &fray, const TrianglePacket &packet) {
  return prefilterPacket<Kz>(fray, packet);
}
template <int Kz>
uint64_t leafPass(const PrefilterRay &fray, const TrianglePacket *packets, uint32_t count) {
  return prefilterLeafAvx2<Kz>(fray, packets, count);
}

uint32_t packetPassFor(int kz, const PrefilterRay &fray, const TrianglePacket &packet) {
  return kz == 0 ? packetPass<0>(fray, packet)
         : kz == 1 ? packetPass<1>(fray, packet)
                   : packetPass<2>(fray, packet);
}
uint64_t sseLeafPassFor(int kz, const PrefilterRay &fray, const TrianglePacket *packets,
                        uint32_t count) {
  return kz == 0 ? prefilterLeaf<0>(fray, packets, count)
         : kz == 1 ? prefilterLeaf<1>(fray, packets, count)
                   : prefilterLeaf<2>(fray, packets, count);
}
uint64_t leafPassFor(int kz, const PrefilterRay &fray, const TrianglePacket *packets,
                     uint32_t count) {
  return kz == 0 ? leafPass<0>(fray, packets, count)
         : kz == 1 ? leafPass<1>(fray, packets, count)
                   : leafPass<2>(fray, packets, count);
}

// The SSE prefilter's verdict; where the CPU has AVX2, also checks that the
// whole-leaf version gives the same verdict for each copy of the packet in
// leaves of 1 to 64 triangles (the bits past the count cleared).
uint32_t prefilter(const WatertightRay &ray, const Bounds3 &box, const TrianglePacket &packet) {
  PrefilterRay fray(ray, box);
  const uint32_t pass = packetPassFor(ray.kz, fray, packet);
  if (cpuHasAvx2()) {
    TrianglePacket leaf[16];
    for (TrianglePacket &p : leaf) p = packet;
    uint64_t expected = 0;
    for (int i = 0; i < 16; ++i) expected |= uint64_t{pass} << (4 * i);
    for (uint32_t count : {1u, 3u, 4u, 5u, 8u, 9u, 13u, 33u, 63u, 64u}) {
      const uint64_t mask = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
      EXPECT_EQ(leafPassFor(ray.kz, fray, leaf, count), expected & mask) << count;
    }
  }
  return pass;
}

struct Counts {
  int hits = 0, rejected = 0, misses = 0;
};

// Four random triangles of size `size` around `center`, and rays aimed at
// their corners, at points of their edges and at random points near them.
Counts probe(uint64_t seed, const Vec3 &center, double size, double spread) {
  Rng rng(seed);
  Counts counts;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int round = 0; round < 400; ++round) {
    TrianglePacket packet;
    Vec3f corners[4][3];
    Bounds3 box;
    for (int lane = 0; lane < 4; ++lane) {
      Vec3 c = center + rng.inBox({-spread, -spread, -spread}, {spread, spread, spread});
      for (Vec3f &p : corners[lane]) {
        p = toFloat(c + rng.direction() * size);
        box.extend(toDouble(p));
      }
      packet.set(lane, corners[lane][0], corners[lane][1], corners[lane][2]);
    }
    for (int k = 0; k < 40; ++k) {
      const Vec3f *tri = corners[k % 4];
      Vec3 a = toDouble(tri[0]), b = toDouble(tri[1]), c = toDouble(tri[2]);
      Vec3 target;
      switch (k % 5) {
      case 0: target = k % 3 == 0 ? a : k % 3 == 1 ? b : c; break;
      case 1: target = a + (b - a) * rng.uniform(); break;
      case 2: target = b + (c - b) * rng.uniform(); break;
      default: {
        double u = rng.uniform(-0.1, 1.1), v = rng.uniform(-0.1, 1.1);
        target = a + (b - a) * u + (c - a) * v;
      }
      }
      Vec3 origin = target + rng.direction() * rng.uniform(0.01, 4) * (1 + std::fabs(center.x));
      Ray ray{origin, target - origin, -kInf, kInf};
      WatertightRay wray(ray);
      uint32_t pass = prefilter(wray, box, packet);
      for (int lane = 0; lane < 4; ++lane) {
        TriangleHitParams p;
        bool hit = intersectTriangle(wray, toDouble(corners[lane][0]), toDouble(corners[lane][1]),
                                     toDouble(corners[lane][2]), kInf, p);
        bool kept = (pass >> lane) & 1;
        if (hit) {
          ++counts.hits;
          EXPECT_TRUE(kept) << "seed " << seed << " round " << round << " ray " << k;
        } else {
          ++counts.misses;
          counts.rejected += !kept;
        }
      }
    }
  }
  return counts;
}

TEST(TrianglePrefilter, KeepsEveryHitAndRejectsMostMisses) {
  Counts c = probe(1, {0, 0, 0}, 1, 3);
  EXPECT_GT(c.hits, 2000);
  EXPECT_GT(c.rejected, c.misses * 8 / 10);
}

TEST(TrianglePrefilter, KeepsHitsOfSmallTrianglesFarFromTheOrigin) {
  for (double offset : {1e3, 1e5}) {
    Counts c = probe(2, {offset, -offset, 0.5 * offset}, 1e-3 * offset * 1e-3, 1e-3 * offset);
    EXPECT_GT(c.hits, 2000) << offset;
  }
}

// A leaf of 16 different packets: each triangle's bit in the whole-leaf
// results (SSE, and AVX2 where the CPU has it) is its own packet's SSE
// verdict, for every leaf size.
TEST(TrianglePrefilter, WholeLeafMatchesPacketByPacket) {
  Rng rng(3);
  int kept = 0, rejected = 0;
  for (int round = 0; round < 200; ++round) {
    TrianglePacket leaf[16];
    Bounds3 box;
    for (TrianglePacket &packet : leaf)
      for (int lane = 0; lane < 4; ++lane) {
        Vec3 c = rng.inBox({-3, -3, -3}, {3, 3, 3});
        Vec3f p[3];
        for (Vec3f &q : p) {
          q = toFloat(c + rng.direction());
          box.extend(toDouble(q));
        }
        packet.set(lane, p[0], p[1], p[2]);
      }
    Vec3 target = rng.inBox({-2, -2, -2}, {2, 2, 2});
    Vec3 origin = target + rng.direction() * 8;
    WatertightRay wray(Ray{origin, target - origin});
    PrefilterRay fray(wray, box);
    uint64_t expected = 0;
    for (int i = 0; i < 16; ++i)
      expected |= uint64_t{packetPassFor(wray.kz, fray, leaf[i])} << (4 * i);
    for (uint32_t count = 1; count <= 64; ++count) {
      const uint64_t mask = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
      ASSERT_EQ(sseLeafPassFor(wray.kz, fray, leaf, count), expected & mask)
          << round << " " << count;
      if (cpuHasAvx2()) {
        ASSERT_EQ(leafPassFor(wray.kz, fray, leaf, count), expected & mask)
            << round << " " << count;
      }
    }
    kept += std::popcount(expected);
    rejected += 64 - std::popcount(expected);
  }
  // Both verdicts occur (the comparison is not between all-ones masks).
  EXPECT_GT(kept, 50);
  EXPECT_GT(rejected, 5000);
}

TEST(TrianglePrefilter, PassesEverythingOutOfFloatRange) {
  TrianglePacket packet;
  for (int lane = 0; lane < 4; ++lane) packet.set(lane, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  Ray ray{{1e35, 1e35, -1e35}, {0, 0, 1}};
  Bounds3 box({0, 0, 0}, {1, 1, 0});
  EXPECT_EQ(prefilter(WatertightRay(ray), box, packet), 0xfu);
}

} // namespace
} // namespace lray
