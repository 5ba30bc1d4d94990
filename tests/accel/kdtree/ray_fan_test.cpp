// Tests for src/accel/kdtree/ray_fan.h: rays from one point bounded
// together keep every box any of them crosses (by FlatInstances's own slab
// test), and only rays that share an origin and their directions' signs
// form a fan.
#include "accel/kdtree/flat_instances.h"
#include "accel/kdtree/kdtree_test_util.h"
#include "accel/kdtree/ray_fan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace lray {
namespace {

using kdtest::Rng;

/// Whether FlatInstances's test of `box` lets `ray` through.
bool slabCrosses(const Bounds3 &box, const Ray &ray) {
  const FlatInstances one(std::vector<Bounds3>{box});
  double tBest = ray.tMax;
  bool tested = false;
  one.forEachCrossed<false>(ray, tBest, [&](uint32_t, double &) {
    tested = true;
    return false;
  });
  return tested;
}

TEST(RayFan, KeepsEveryBoxAnyOfItsRaysCrosses) {
  Rng rng(31);
  int kept = 0, culled = 0, crossedByOne = 0;
  for (int f = 0; f < 300; ++f) {
    // A tile's camera rays: one origin, directions over a small square.
    const Vec3 o = rng.inBox({-20, -20, -20}, {20, 20, 20});
    const Vec3 centre = rng.inBox({-1, -1, -1}, {1, 1, 1});
    const double spread = f % 3 == 0 ? 0.3 : 0.01;
    std::vector<Ray> rays;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) {
        Ray r{o, centre + Vec3(x * spread / 16, y * spread / 16, 0.5 * spread)};
        r.tMin = f % 2 ? 0 : 1e-6 * (x + 1);
        r.tMax = f % 4 == 0 ? 2 + y : std::numeric_limits<double>::infinity();
        rays.push_back(r);
      }
    RayFan fan;
    if (!fan.gather(rays.data(), rays.size())) continue;
    for (int b = 0; b < 60; ++b) {
      Bounds3 box;
      if (b % 3 == 0) {
        // A corner exactly on one of the rays: crossed by a hair.
        const Ray &r = rays[static_cast<size_t>(rng.uniform(0, 1) * rays.size()) % rays.size()];
        const Vec3 corner = r.at(rng.uniform(0.5, 1.5));
        box.extend(corner);
        box.extend(corner + rng.inBox({-1, -1, -1}, {1, 1, 1}) * rng.uniform(0, 0.5));
      } else {
        const Vec3 c = o + centre * rng.uniform(0, 10) + rng.inBox({-3, -3, -3}, {3, 3, 3});
        box.extend(c);
        box.extend(c + rng.inBox({0, 0, 0}, {1, 1, 1}) * rng.uniform(0.01, 2));
      }
      bool any = false;
      for (const Ray &r : rays) any = any || slabCrosses(box, r);
      const bool may = fan.mayCross(box);
      if (any) {
        ++crossedByOne;
        ASSERT_TRUE(may) << "fan " << f << " box " << b;
      }
      (may ? kept : culled) += 1;
    }
  }
  EXPECT_GT(crossedByOne, 2000);
  EXPECT_GT(culled, 2000); // and it does cull
}

TEST(RayFan, FormsOnlyFromOneOriginAndSteadySigns) {
  const std::vector<Ray> good = {{{1, 2, 3}, {0.1, -0.2, 1}}, {{1, 2, 3}, {0.2, -0.1, 1}}};
  RayFan fan;
  EXPECT_TRUE(fan.gather(good.data(), good.size()));
  EXPECT_FALSE(fan.gather(good.data(), 0));
  std::vector<Ray> rays = good;
  rays[1].o.x = std::nextafter(1.0, 2.0);
  EXPECT_FALSE(fan.gather(rays.data(), rays.size())) << "two origins";
  rays = good;
  rays[1].d.x = -0.1;
  EXPECT_FALSE(fan.gather(rays.data(), rays.size())) << "a sign changes";
  rays = good;
  rays[0].d.y = 0;
  EXPECT_FALSE(fan.gather(rays.data(), rays.size())) << "a zero component";
  rays = good;
  rays[1].tMax = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fan.gather(rays.data(), rays.size())) << "a NaN bound";
  rays = good;
  rays[0].d.z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fan.gather(rays.data(), rays.size())) << "a NaN direction";
}

} // namespace
} // namespace lray
