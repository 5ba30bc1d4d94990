// SphereBound (src/geometry/shapes/sphere_bound.h): a still sphere's world
// bounding sphere settles only lines its own test misses, and settles the
// clear misses of a sphere placed by a rotation and one scale.
#include "geometry/shape.h"
#include "geometry/shapes/sphere_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace lray {
namespace {

Entity sphereAt(const Transform &worldFromObject) {
  Entity e;
  e.shape = Sphere{};
  e.worldFromObject = worldFromObject;
  return e;
}

/// The whole line: any root of the sphere's own test counts.
Ray line(const Vec3 &o, const Vec3 &d) {
  Ray r{o, d};
  r.tMin = -std::numeric_limits<double>::max();
  r.tMax = std::numeric_limits<double>::max();
  return r;
}

Vec3 randomUnit(std::mt19937_64 &rng) {
  std::normal_distribution<double> g;
  Vec3 v{g(rng), g(rng), g(rng)};
  return v / length(v);
}

TEST(SphereBound, SettlesOnlyLinesTheSphereMisses) {
  // Placements from 1e-4 to 1e4 in size, up to 1e4 from the origin, some
  // stretched (up to past kMaxStretch); lines passing from 0.9 to 1.1 times
  // the bound's radius, from origins up to 1e7 radii away: every line the
  // bound settles, the sphere's own tests miss.
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(-1, 1), logU(-4, 4), stretch(0, 3.5);
  int settled = 0, lines = 0, hits = 0;
  for (int p = 0; p < 400; ++p) {
    const double size = std::pow(10.0, logU(rng));
    const double sy = p % 4 == 0 ? std::pow(10.0, stretch(rng)) : 1;
    const Vec3 at = Vec3(u(rng), u(rng), u(rng)) * (1e4 * std::fabs(u(rng)));
    const Transform turn = Transform::rotate(randomUnit(rng), 180 * u(rng));
    const Transform xf = Transform::translate(at) * turn * Transform::scale(size, size * sy, size);
    const Entity e = sphereAt(xf);
    const SphereBound bound(xf);
    const Vec3 centre = xf.applyPoint({0, 0, 0});
    const double radius = size * std::max(sy, 1.0);
    for (int k = 0; k < 500; ++k) {
      // A line through the point `pass` radii out along a random normal.
      const Vec3 d = randomUnit(rng) * std::pow(10.0, 2 * u(rng));
      Vec3 side = cross(d, randomUnit(rng));
      side = side / length(side);
      const double pass = 1 + 0.1 * u(rng);
      const Vec3 closest = centre + side * (pass * radius);
      const double back = radius * std::pow(10.0, 7 * std::fabs(u(rng))) * u(rng);
      const Vec3 o = closest - d / length(d) * back;
      const Ray r = line(o, d);
      ++lines;
      Hit h;
      const bool hit = intersectShape(e, 0, r, r.tMax, h);
      hits += hit;
      if (!bound.missesLine(r)) continue;
      ++settled;
      ASSERT_FALSE(hit) << "placement " << p << " line " << k;
      ASSERT_FALSE(occludedStillSphere(e, r, r.tMax)) << "placement " << p << " line " << k;
    }
  }
  // Both kinds of line occur, and the bound settles a good share.
  EXPECT_GT(hits, lines / 10);
  EXPECT_GT(settled, lines / 5);
}

TEST(SphereBound, FourLanesAreFourLines) {
  // missesLines decides each lane as missesLine does its ray, bit for bit:
  // lines on both sides of the margin, far origins, NaN.
  std::mt19937_64 rng(44);
  std::uniform_real_distribution<double> u(-1, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  int settled = 0, open = 0;
  for (int p = 0; p < 200; ++p) {
    const double size = std::pow(10.0, 3 * u(rng));
    const Transform xf = Transform::translate(Vec3(u(rng), u(rng), u(rng)) * 100) *
                         Transform::rotate(randomUnit(rng), 90 * u(rng)) *
                         Transform::scale(size, size * (1 + 0.5 * std::fabs(u(rng))), size);
    const SphereBound bound(xf);
    const Vec3 centre = xf.applyPoint({0, 0, 0});
    for (int k = 0; k < 50; ++k) {
      Ray rays[4];
      for (Ray &r : rays) {
        const Vec3 d = randomUnit(rng);
        Vec3 side = cross(d, randomUnit(rng));
        side = side / length(side);
        const double pass = size * 1.5 * (1 + 0.002 * u(rng)) * std::fabs(u(rng)) * 2;
        r = line(centre + side * pass - d * (size * std::pow(10.0, 8 * std::fabs(u(rng)))), d);
        if (rng() % 50 == 0) r.o.y = nan;
      }
      const Ray *const four[4] = {&rays[0], &rays[1], &rays[2], &rays[3]};
      const uint32_t bits = bound.missesLines(four);
      for (int i = 0; i < 4; ++i) {
        ASSERT_EQ((bits >> i & 1u) != 0, bound.missesLine(rays[i])) << p << " " << k << " " << i;
        (bound.missesLine(rays[i]) ? settled : open) += 1;
      }
    }
  }
  EXPECT_GT(settled, 5000);
  EXPECT_GT(open, 5000);
}

TEST(SphereBound, SettlesClearMissesOfASimilarity) {
  const Transform xf = Transform::translate({30, -2, 7}) * Transform::rotate({1, 2, 3}, 40) *
                       Transform::scale(2.5, 2.5, 2.5);
  const SphereBound bound(xf);
  const Vec3 centre{30, -2, 7};
  const Vec3 d{0.3, -1, 0.2};
  Vec3 side = cross(d, Vec3(1, 0, 0));
  side = side / length(side);
  for (double pass : {1.01, 1.5, 10.0, 1e5})
    EXPECT_TRUE(bound.missesLine(line(centre + side * (2.5 * pass) - d * 40, d))) << pass;
  // Within the clear margin (or through the sphere): left to its own test.
  for (double pass : {0.0, 0.5, 0.999, 1.0001})
    EXPECT_FALSE(bound.missesLine(line(centre + side * (2.5 * pass) - d * 40, d))) << pass;
}

TEST(SphereBound, SettlesNothingWhereItCannotVouch) {
  const Vec3 o{0, 100, 0}, d{1, 0, 0}; // passes 100 radii from the origin
  EXPECT_FALSE(SphereBound().missesLine(line(o, d)));
  // Stretched past kMaxStretch.
  EXPECT_FALSE(SphereBound(Transform::scale(1, 1, 1e-4)).missesLine(line(o, d)));
  // Farther than kFar radii from the world's origin.
  EXPECT_FALSE(SphereBound(Transform::translate({0, 0, 1e7})).missesLine(line(o, d)));
  // An origin farther than kFar radii from the sphere.
  EXPECT_FALSE(SphereBound(Transform()).missesLine(line({-1e7, 100, 0}, d)));
  EXPECT_TRUE(SphereBound(Transform()).missesLine(line({-1e5, 100, 0}, d)));
  // Rays that are not rays.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(SphereBound(Transform()).missesLine(line({nan, 100, 0}, d)));
  EXPECT_FALSE(SphereBound(Transform()).missesLine(line(o, {0, 0, 0})));
}

} // namespace
} // namespace lray
