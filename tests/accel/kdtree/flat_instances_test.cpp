// Tests for src/accel/kdtree/flat_instances.h: the top level of a scene of
// a few entities as a list of boxes.
#include "accel/kdtree/flat_instances.h"
#include "accel/kdtree/kdtree_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace lray {
namespace {

using kdtest::Rng;

/// Where the segment (tMin, tMax) of `ray` meets `box` by the exact slab
/// rule (no slack): the entry and exit t, or false.
bool meets(const Bounds3 &box, const Ray &ray, double tMax, double &t0, double &t1) {
  t0 = ray.tMin;
  t1 = tMax;
  const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
  const double lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
  for (int a = 0; a < 3; ++a) {
    double n = (lo[a] - o[a]) / d[a], f = (hi[a] - o[a]) / d[a];
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
  }
  return t0 <= t1;
}

std::vector<uint32_t> crossed(const FlatInstances &flat, const Ray &ray, double tMax) {
  std::vector<uint32_t> tested;
  flat.forEachCrossed<false>(ray, tMax, [&](uint32_t i, double &) {
    tested.push_back(i);
    return false;
  });
  return tested;
}

TEST(FlatInstances, TestsTheBoxesTheSegmentCrossesNearestFirst) {
  Rng rng(7);
  std::vector<Bounds3> boxes;
  for (size_t i = 0; i < FlatInstances::kMaxInstances; ++i) {
    const Vec3 c = rng.inBox({-5, -5, -5}, {5, 5, 5});
    boxes.push_back({c - Vec3(1, 0.5, 2) * rng.uniform(0.2, 1), c + Vec3(1, 2, 0.5)});
  }
  const FlatInstances flat(boxes);
  ASSERT_FALSE(flat.empty());
  int clear = 0;
  for (int k = 0; k < 4000; ++k) {
    Ray ray;
    ray.o = rng.inBox({-9, -9, -9}, {9, 9, 9});
    ray.d = rng.direction();
    const double tMax = k % 2 ? rng.uniform(0.5, 12) : ray.tMax;
    const std::vector<uint32_t> tested = crossed(flat, ray, tMax);
    // By their entry (equal ones within the slack either way).
    for (size_t j = 1; j < tested.size(); ++j) {
      double a0, a1, b0, b1;
      meets(boxes[tested[j - 1]], ray, tMax, a0, a1);
      meets(boxes[tested[j]], ray, tMax, b0, b1);
      EXPECT_LE(a0, b0 + 1e-6 * (1 + std::fabs(b0))) << "ray " << k << " step " << j;
    }
    for (uint32_t i = 0; i < boxes.size(); ++i) {
      double t0, t1;
      const bool hit = meets(boxes[i], ray, tMax, t0, t1);
      const bool wasTested = std::count(tested.begin(), tested.end(), i) == 1;
      // Every box met is tested; a box missed by a clear margin is not
      // (within the slack, either answer is right).
      if (hit) {
        EXPECT_TRUE(wasTested) << "ray " << k << " box " << i;
      }
      if (!hit && !(t0 <= t1 + 1e-6 * (1 + std::fabs(t1)))) {
        EXPECT_FALSE(wasTested) << "ray " << k << " box " << i;
        ++clear;
      }
    }
  }
  EXPECT_GT(clear, 4000); // the misses were exercised
}

TEST(FlatInstances, ARayParallelToAFaceAndLyingOnItCrossesTheBox) {
  const FlatInstances flat(
      {Bounds3(Vec3(0, 0, 0), Vec3(1, 1, 1)), Bounds3(Vec3(3, 0, 0), Vec3(4, 1, 1))});
  Ray onFace{Vec3(-1, 1, 0.5), Vec3(1, 0, 0)}; // y = 1, the top faces
  EXPECT_EQ(crossed(flat, onFace, onFace.tMax), (std::vector<uint32_t>{0, 1}));
  Ray above{Vec3(-1, 1.001, 0.5), Vec3(1, 0, 0)};
  EXPECT_TRUE(crossed(flat, above, above.tMax).empty());
  // The segment ends before the second box.
  EXPECT_EQ(crossed(flat, onFace, 2.5), (std::vector<uint32_t>{0}));
}

TEST(FlatInstances, ANearerHitSkipsTheBoxesBeyondItAndAnyHitStopsAtTheFirst) {
  const FlatInstances flat({Bounds3(Vec3(5, -1, -1), Vec3(6, 1, 1)),
                            Bounds3(Vec3(1, -1, -1), Vec3(2, 1, 1)),
                            Bounds3(Vec3(8, -1, -1), Vec3(9, 1, 1))});
  const Ray ray{Vec3(0, 0, 0), Vec3(1, 0, 0)};
  // Box 0 is hit at 5, box 1 then at 1 (nearer), so box 2 (from 8) is past
  // the nearest and never tested.
  std::vector<uint32_t> tested;
  double tBest = ray.tMax;
  EXPECT_TRUE(flat.forEachCrossed<false>(ray, tBest, [&](uint32_t i, double &t) {
    tested.push_back(i);
    t = i == 0 ? 5 : 1;
    return true;
  }));
  EXPECT_EQ(tested, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(tBest, 1);
  tested.clear();
  tBest = ray.tMax;
  EXPECT_TRUE(flat.forEachCrossed<true>(ray, tBest, [&](uint32_t i, double &) {
    tested.push_back(i);
    return true;
  }));
  EXPECT_EQ(tested, (std::vector<uint32_t>{0}));
}

TEST(FlatInstances, TheNearestBoxIsTestedFirstAndTheOnesPastItsHitNever) {
  // Boxes 0 and 2 behind box 1 along the ray (no axis parallel to it, the
  // general path); 3 and 4 alike, at box 2.
  const Bounds3 second(Vec3(5, -1, -1), Vec3(6, 1, 1)), first(Vec3(1, -1, -1), Vec3(2, 1, 1)),
      third(Vec3(8, -1, -1), Vec3(9, 1, 1));
  const FlatInstances flat({second, first, third, third, third});
  const Ray ray{Vec3(0, 0.001, 0.002), Vec3(1, 0.001, 0.001)};
  std::vector<uint32_t> tested;
  double tBest = ray.tMax;
  auto record = [&](double hitAt) {
    return [&, hitAt](uint32_t i, double &t) {
      tested.push_back(i);
      if (hitAt <= 0) return false;
      t = hitAt;
      return true;
    };
  };
  // Box 1 is hit at 1.5: no other box begins before it.
  EXPECT_TRUE(flat.forEachCrossed<false>(ray, tBest, record(1.5)));
  EXPECT_EQ(tested, (std::vector<uint32_t>{1}));
  EXPECT_EQ(tBest, 1.5);
  // Nothing hit: every box, nearest first, the first kept of equal ones
  // first.
  tested.clear();
  tBest = ray.tMax;
  EXPECT_FALSE(flat.forEachCrossed<false>(ray, tBest, record(0)));
  EXPECT_EQ(tested, (std::vector<uint32_t>{1, 0, 2, 3, 4}));
  // Any hit: in the order kept.
  tested.clear();
  EXPECT_FALSE(flat.forEachCrossed<true>(ray, tBest, record(0)));
  EXPECT_EQ(tested, (std::vector<uint32_t>{0, 1, 2, 3, 4}));
}

TEST(FlatInstances, ManyEntitiesWalkTheTreeInstead) {
  std::vector<Bounds3> boxes(FlatInstances::kMaxInstances + 1,
                             Bounds3(Vec3(0, 0, 0), Vec3(1, 1, 1)));
  EXPECT_TRUE(FlatInstances(boxes).empty());
  boxes.pop_back();
  EXPECT_FALSE(FlatInstances(boxes).empty());
}

} // namespace
} // namespace lray
