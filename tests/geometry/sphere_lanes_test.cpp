// intersectStillSphereLanes and occludedStillSphereLanes (src/geometry/
// shape.h, shapes/sphere_lanes.h): four rays tested together against a
// still sphere give the hits that intersectShape gives each of them, bit
// for bit, and occludedStillSphere's answers.
#include "geometry/shape.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace lray {
namespace {

Vec3 randomUnit(std::mt19937_64 &rng) {
  std::normal_distribution<double> g;
  Vec3 v{g(rng), g(rng), g(rng)};
  return v / length(v);
}

bool sameBits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}
bool sameBits(const Vec3 &a, const Vec3 &b) {
  return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}

/// Every field intersectShape fills.
void expectSameHit(const Hit &a, const Hit &b, const std::string &where) {
  EXPECT_TRUE(sameBits(a.t, b.t)) << where << ": t " << a.t << " " << b.t;
  EXPECT_EQ(a.entity, b.entity) << where;
  EXPECT_EQ(a.primitive, b.primitive) << where;
  EXPECT_TRUE(sameBits(a.p, b.p)) << where;
  EXPECT_TRUE(sameBits(a.pObject, b.pObject)) << where;
  EXPECT_TRUE(sameBits(a.ng, b.ng)) << where;
  EXPECT_TRUE(sameBits(a.ns, b.ns)) << where;
  EXPECT_TRUE(sameBits(a.u, b.u) && sameBits(a.v, b.v)) << where;
  EXPECT_TRUE(sameBits(a.pError, b.pError)) << where;
  EXPECT_EQ(a.time, b.time) << where;
}

TEST(SphereLanes, FourRaysAreFourRays) {
  // Placements from 1e-4 to 1e4 in size, up to 1e4 from the origin, some
  // stretched; rays aimed within 1.2 radii of the centre (hits, grazing
  // hits that take the refinement, misses), from up to 1e6 radii away (the
  // origin shift) or from inside, some with tMin > 0, bounds that cut the
  // hit off, a zero direction; lanes left out of the test.
  std::mt19937_64 rng(34);
  std::uniform_real_distribution<double> u(-1, 1), logU(-4, 4), stretch(0, 2);
  int hits = 0, misses = 0, shifted = 0, tested = 0;
  for (int p = 0; p < 200; ++p) {
    const double size = std::pow(10.0, logU(rng));
    const double sy = p % 3 == 0 ? std::pow(10.0, stretch(rng)) : 1;
    const Vec3 at = Vec3(u(rng), u(rng), u(rng)) * (1e4 * std::fabs(u(rng)));
    const Transform xf = Transform::translate(at) *
                         Transform::rotate(randomUnit(rng), 180 * u(rng)) *
                         Transform::scale(size, size * sy, size);
    Entity e;
    e.shape = Sphere{};
    e.worldFromObject = xf;
    e.readsUv = p % 2 == 0;
    ASSERT_TRUE(isStillSphere(e));
    const Vec3 centre = xf.applyPoint({0, 0, 0});
    const double radius = size * std::max(sy, 1.0);
    for (int group = 0; group < 100; ++group) {
      Ray rays[4];
      double tMax[4];
      for (int k = 0; k < 4; ++k) {
        const Vec3 target = centre + randomUnit(rng) * (radius * 1.2 * std::fabs(u(rng)));
        const double away = radius * std::pow(10.0, 6 * std::fabs(u(rng)));
        const Vec3 o = group % 7 == 0 ? centre + randomUnit(rng) * (0.5 * radius)
                                      : target - randomUnit(rng) * away;
        Vec3 d = (target - o) * std::pow(10.0, u(rng));
        if (group % 50 == 1 && k == 2) d = {0, 0, 0};
        rays[k] = Ray{o, d, group % 5 == 0 ? 0.3 : 0.0, std::numeric_limits<double>::infinity(),
                      static_cast<float>(0.25 * k)};
        tMax[k] = group % 4 == 3 ? std::fabs(u(rng)) * 1.5 : rays[k].tMax;
        shifted += (maxAbsComponent(xf.inverse().applyPoint(o)) > 4);
      }
      const uint32_t open = group % 6 == 5 ? 0b1011 : 0b1111;
      const Ray *laneRays[4] = {&rays[0], &rays[1], &rays[2], &rays[3]};
      Hit got[4];
      Hit *const out[4] = {&got[0], &got[1], &got[2], &got[3]};
      const uint32_t found = intersectStillSphereLanes(e, 7, laneRays, tMax, open, out);
      const uint32_t blocked = occludedStillSphereLanes(e, laneRays, tMax);
      EXPECT_EQ(found & ~open, 0u);
      for (int k = 0; k < 4; ++k) {
        if (!(open >> k & 1u)) continue;
        ++tested;
        Hit want;
        const bool hit = intersectShape(e, 7, rays[k], tMax[k], want);
        const std::string where = "placement " + std::to_string(p) + " group " +
                                  std::to_string(group) + " lane " + std::to_string(k);
        ASSERT_EQ(bool(found >> k & 1u), hit) << where;
        ASSERT_EQ(bool(blocked >> k & 1u), occludedStillSphere(e, rays[k], tMax[k])) << where;
        if (!hit) {
          ++misses;
          continue;
        }
        ++hits;
        expectSameHit(got[k], want, where);
      }
    }
  }
  EXPECT_GT(hits, tested / 4);
  EXPECT_GT(misses, tested / 10);
  EXPECT_GT(shifted, tested / 4);
}

} // namespace
} // namespace lray
