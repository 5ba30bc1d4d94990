// toRay8 (src/accel/embree/embree_rays.h) converts four rays at a time in
// vectors: every lane must hold exactly what toRay1 writes for its ray,
// including bounds that are not floats (rounded outwards), NaN, -0 and
// partial packets.
#include "accel/embree/embree_rays.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace lray {
namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectLaneIsRay1(const RTCRay8 &r8, unsigned i, const Ray &ray, const Vec3 &origin) {
  RTCRay r1;
  toRay1(ray, origin, r1);
  EXPECT_TRUE(sameBits(r8.org_x[i], r1.org_x) && sameBits(r8.org_y[i], r1.org_y) &&
              sameBits(r8.org_z[i], r1.org_z))
      << "lane " << i;
  EXPECT_TRUE(sameBits(r8.dir_x[i], r1.dir_x) && sameBits(r8.dir_y[i], r1.dir_y) &&
              sameBits(r8.dir_z[i], r1.dir_z))
      << "lane " << i;
  EXPECT_TRUE(sameBits(r8.tnear[i], r1.tnear)) << "lane " << i << " tMin " << ray.tMin;
  EXPECT_TRUE(sameBits(r8.tfar[i], r1.tfar)) << "lane " << i << " tMax " << ray.tMax;
  EXPECT_TRUE(sameBits(r8.time[i], r1.time)) << "lane " << i;
  EXPECT_EQ(r8.mask[i], r1.mask);
  EXPECT_EQ(r8.id[i], i);
  EXPECT_EQ(r8.flags[i], r1.flags);
}

TEST(EmbreeRays, EightLanesAreEightSingleRays) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // Bounds of every kind: floats, doubles between floats, beyond float's
  // range, NaN, signed zeros, infinities.
  const double specials[] = {0.0, -0.0, 1e-3, 0.1, 1.0 / 3, -2.5, 1e39, -1e39, nan, inf, -inf};
  int inexact = 0;
  for (int packet = 0; packet < 2000; ++packet) {
    const Vec3 origin = packet % 3 == 0 ? Vec3(1e4 * u(rng), 1e4 * u(rng), 3) : Vec3();
    Ray rays[8];
    for (Ray &r : rays) {
      r.o = Vec3(u(rng), u(rng), u(rng)) * 1e5;
      r.d = Vec3(u(rng), u(rng), u(rng));
      r.tMin = packet % 2 ? specials[rng() % std::size(specials)] : std::fabs(u(rng)) * 1e-6;
      r.tMax = packet % 2 ? specials[rng() % std::size(specials)] : inf;
      r.time = static_cast<float>(std::fabs(u(rng)));
      inexact += static_cast<double>(static_cast<float>(r.tMin)) != r.tMin;
    }
    const size_t lanes = packet % 5 == 0 ? 1 + rng() % 8 : 8;
    RTCRay8 r8;
    int valid[8];
    toRay8(rays, lanes, origin, r8, valid);
    for (unsigned i = 0; i < 8; ++i) {
      EXPECT_EQ(valid[i], i < lanes ? -1 : 0);
      expectLaneIsRay1(r8, i, rays[i < lanes ? i : 0], origin);
    }
  }
  EXPECT_GT(inexact, 1000); // the outward rounding is exercised
}

TEST(EmbreeRays, HitRecordsStartEmpty) {
  Ray rays[3];
  rays[1].tMax = 7;
  RTCRayHit8 rh;
  int valid[8];
  double bestT[8];
  toRayHit8(rays, 3, Vec3(), rh, valid, bestT);
  for (unsigned i = 0; i < 8; ++i) {
    EXPECT_EQ(rh.hit.geomID[i], RTC_INVALID_GEOMETRY_ID);
    EXPECT_EQ(rh.hit.instID[0][i], RTC_INVALID_GEOMETRY_ID);
    EXPECT_EQ(bestT[i], rays[i < 3 ? i : 0].tMax);
  }
}

} // namespace
} // namespace lray
