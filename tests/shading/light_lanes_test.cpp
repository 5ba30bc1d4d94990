// Tests for src/shading/light_lanes: a round of a Light's cell in lanes
// gives each point what the integrator's loop gives it one point at a time
// (Light::Sampler::sample, spawnRayTo, phongColor), bit for bit, on the
// scalar path and in AVX2 lanes.
#include "shading/light_lanes.h"

#include "math/mix64.h"
#include "math/random.h"
#include "util/cpu_features.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

namespace lray {
namespace {

uint64_t bitsOf(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

#define EXPECT_SAME_BITS(a, b) EXPECT_EQ(bitsOf(a), bitsOf(b)) << #a << " = " << (a)

/// A unit vector from two uniform numbers.
Vec3 unitFrom(double u, double v) {
  const double z = 2 * u - 1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 6.283185307179586 * v;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Finishes with every kind of highlight the lanes treat apart: none, a
/// zero exponent, small and largest integer exponents, a non-integer and
/// a large one (std::pow).
std::deque<Material> materials() {
  std::deque<Material> out;
  const double exponents[] = {0, 1, 2, 5, 37, 64, 65, 128, 1024, 1025, 2.5};
  for (double specular : {0.0, 0.8}) {
    for (double e : exponents) {
      Finish f;
      f.diffuse = 0.7;
      f.specular = specular;
      f.exponent = e;
      out.push_back(Material::prepare(f, 0, true));
    }
  }
  return out;
}

struct Case {
  Hit hit;
  Vec3 n, v;
  Color pigment;
  const Material *m;
};

/// `count` random points around a light of unit size at the origin, some
/// behind it, some far away, one on its plane (N.L = 0), one at the
/// centre of the light's first cell (distance 0 there).
std::vector<Case> cases(size_t count, uint64_t seed, const std::deque<Material> &ms) {
  std::vector<Case> out;
  Sampler random(seed, 0, 0);
  for (size_t i = 0; i < count; ++i) {
    Case c;
    const double scale = i % 7 == 6 ? 1e4 : 3;
    c.hit.p = {scale * (2 * random.next() - 1), scale * (2 * random.next() - 1),
               scale * (2 * random.next() - 1)};
    if (i % 11 == 5) c.hit.p.y = 0;
    c.hit.ng = unitFrom(random.next(), random.next());
    c.hit.pError = 1e-15 * scale * random.next();
    c.hit.time = static_cast<float>(random.next());
    c.n = random.next() < 0.5 ? c.hit.ng : -c.hit.ng;
    if (i % 11 == 5) c.n = {0, 1, 0};
    c.v = unitFrom(random.next(), random.next());
    c.pigment = {random.next(), random.next(), random.next()};
    c.m = &ms[i % ms.size()];
    out.push_back(c);
  }
  return out;
}

Light areaLight() {
  Light light;
  light.rows = 3;
  light.cols = 4;
  light.area = true;
  light.color = {0.9, 0.7, 0.5};
  light.worldFromLight = Transform::translate({0.5, 2, -1}) *
                         Transform::rotate({1, 0.3, 0.2}, 35) * Transform::scale(2, 1, 3);
  return light;
}

/// Every round of every cell: the lanes' outputs against the loop's
/// formulas for one point, with each point's own sampler.
void checkPath(bool avx2) {
  const std::deque<Material> ms = materials();
  const Light light = areaLight();
  const Light::Sampler sampler(light);
  for (size_t count : {size_t{1}, size_t{3}, size_t{4}, size_t{37}, LightLanes::kMax}) {
    const std::vector<Case> cs = cases(count, count, ms);
    static LightLanes lanes;
    lanes.clear();
    std::vector<Sampler> samplers;
    for (size_t i = 0; i < count; ++i) {
      const Case &c = cs[i];
      lanes.add(static_cast<uint32_t>(i), c.hit, spawnOrigins(c.hit), c.n, c.v, c.pigment, *c.m);
      samplers.emplace_back(7, i, 1);
    }
    std::vector<Sampler> reference = samplers;
    for (int row = 0; row < light.rows; ++row) {
      for (int col = 0; col < light.cols; ++col) {
        for (size_t j = 0; j < count; ++j) {
          sampler.place(row, col, samplers[j], lanes.ax[j], lanes.az[j]);
          lanes.active[j] = j % 13 != 12; // a point now and then takes no sample
        }
        const LightRound round =
            detail::lightLanesRound(lanes, {0, lanes.count}, sampler.grid(), avx2);
        size_t valid = 0;
        Bounds3 from, to;
        for (size_t j = 0; j < count; ++j) {
          const Case &c = cs[j];
          const LightSample s = sampler.sample(row * light.cols + col, c.hit.p, reference[j]);
          const Vec3 toLight = s.target - c.hit.p;
          const double dist = length(toLight);
          const Vec3 l = toLight / dist;
          const double nl = dot(c.n, l);
          const bool expected = lanes.active[j] && dist > 0 && !(nl <= 0);
          ASSERT_EQ(lanes.valid[j], expected) << "lane " << j << " of " << count;
          if (!expected) continue;
          ++valid;
          Ray ray;
          spawnRayTo(spawnOrigins(c.hit), c.hit, s.target, ray);
          EXPECT_SAME_BITS(lanes.ox[j], ray.o.x);
          EXPECT_SAME_BITS(lanes.oy[j], ray.o.y);
          EXPECT_SAME_BITS(lanes.oz[j], ray.o.z);
          EXPECT_SAME_BITS(lanes.dx[j], ray.d.x);
          EXPECT_SAME_BITS(lanes.dy[j], ray.d.y);
          EXPECT_SAME_BITS(lanes.dz[j], ray.d.z);
          const Color color =
              phongColor(c.n, c.v, l, nl, c.pigment * c.m->finish.diffuse, *c.m);
          EXPECT_SAME_BITS(lanes.cr[j], color.r);
          EXPECT_SAME_BITS(lanes.cg[j], color.g);
          EXPECT_SAME_BITS(lanes.cb[j], color.b);
          from.extend(ray.o);
          to.extend(ray.o + ray.d);
        }
        EXPECT_EQ(round.valid, valid);
        ASSERT_TRUE(round.finite);
        if (valid == 0) continue;
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(round.from.lo[k], from.lo[k]);
          EXPECT_EQ(round.from.hi[k], from.hi[k]);
          EXPECT_EQ(round.to.lo[k], to.lo[k]);
          EXPECT_EQ(round.to.hi[k], to.hi[k]);
        }
      }
    }
  }
}

TEST(LightLanes, ScalarPathIsTheLightLoop) { checkPath(false); }

TEST(LightLanes, Avx2PathIsTheLightLoop) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkPath(true);
}

/// A ray with a coordinate not finite (here from an infinite error bound
/// on its hit point) makes the round say its boxes are not to be trusted
/// (the caller bounds the written rays instead).
void checkNotFinite(bool avx2) {
  const std::deque<Material> ms = materials();
  std::vector<Case> cs = cases(6, 3, ms);
  cs[4].hit.p = {0.5, 0, -1};
  cs[4].hit.ng = cs[4].n = {0, 1, 0};
  cs[4].hit.pError = std::numeric_limits<double>::infinity();
  static LightLanes lanes;
  lanes.clear();
  for (size_t i = 0; i < cs.size(); ++i)
    lanes.add(static_cast<uint32_t>(i), cs[i].hit, spawnOrigins(cs[i].hit), cs[i].n, cs[i].v,
              cs[i].pigment, *cs[i].m);
  const Light::Sampler sampler(areaLight());
  for (size_t j = 0; j < cs.size(); ++j) lanes.ax[j] = lanes.az[j] = 0.5, lanes.active[j] = 1;
  const LightRound round = detail::lightLanesRound(lanes, {0, lanes.count}, sampler.grid(), avx2);
  ASSERT_TRUE(lanes.valid[4]);
  EXPECT_FALSE(round.finite);
}

TEST(LightLanes, ScalarPathFlagsInfiniteRays) { checkNotFinite(false); }

TEST(LightLanes, Avx2PathFlagsInfiniteRays) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkNotFinite(true);
}

/// addLit adds lightColor * c * weight to the lanes flagged, as Color's
/// operators do, and leaves the others alone.
void checkAddLit(bool avx2, double weight) {
  static LightLanes lanes;
  lanes.clear();
  lanes.count = 13;
  uint8_t add[LightLanes::kMax] = {};
  const Color light{0.3, 0.55, 0.7};
  for (size_t j = 0; j < lanes.count; ++j) {
    const double x = static_cast<double>(mix64(j) >> 11) * 0x1p-53;
    lanes.cr[j] = x, lanes.cg[j] = 1 - x, lanes.cb[j] = x * x;
    lanes.sr[j] = 0.1 * j, lanes.sg[j] = 0.2, lanes.sb[j] = x / 3;
    add[j] = j % 3 != 1;
  }
  Color expected[LightLanes::kMax];
  for (size_t j = 0; j < lanes.count; ++j) {
    expected[j] = {lanes.sr[j], lanes.sg[j], lanes.sb[j]};
    if (add[j]) expected[j] += light * Color(lanes.cr[j], lanes.cg[j], lanes.cb[j]) * weight;
  }
  detail::addLit(lanes, {0, lanes.count}, {lanes.cr, lanes.cg, lanes.cb}, light, weight, add,
                 avx2);
  for (size_t j = 0; j < lanes.count; ++j) {
    EXPECT_SAME_BITS(lanes.sr[j], expected[j].r);
    EXPECT_SAME_BITS(lanes.sg[j], expected[j].g);
    EXPECT_SAME_BITS(lanes.sb[j], expected[j].b);
  }
}

/// placeLanes draws what Light::Sampler::place draws with each point's
/// sampler, and leaves each sampler where place leaves it; a stratified
/// sampler keeps the drawing to the samplers themselves.
void checkPlace(bool avx2) {
  const std::deque<Material> ms = materials();
  const std::vector<Case> cs = cases(LightLanes::kMax - 3, 5, ms);
  for (bool area : {true, false}) {
    Light light = areaLight();
    light.area = area;
    const Light::Sampler sampler(light);
    static LightLanes lanes;
    lanes.clear();
    std::vector<Sampler> samplers, reference;
    for (size_t i = 0; i < cs.size(); ++i) {
      lanes.add(static_cast<uint32_t>(i), cs[i].hit, spawnOrigins(cs[i].hit), cs[i].n, cs[i].v,
                cs[i].pigment, *cs[i].m);
      samplers.emplace_back(3, i, 2);
      samplers.back().next(); // a number drawn before (odd counts too)
      if (i % 2) samplers.back().next();
    }
    reference = samplers;
    ASSERT_TRUE(loadSamplers(lanes, samplers.data()));
    for (int row = 0; row < light.rows; ++row) {
      for (int col = 0; col < light.cols; ++col) {
        detail::placeLanes(lanes, {0, lanes.count}, sampler, row, col, avx2);
        for (size_t j = 0; j < lanes.count; ++j) {
          double a, b;
          sampler.place(row, col, reference[j], a, b);
          EXPECT_SAME_BITS(lanes.ax[j], a);
          EXPECT_SAME_BITS(lanes.az[j], b);
        }
      }
    }
    storeSamplers(lanes, samplers.data());
    for (size_t j = 0; j < lanes.count; ++j) EXPECT_EQ(samplers[j].next(), reference[j].next());
    samplers[7].stratify(0, 1);
    EXPECT_FALSE(loadSamplers(lanes, samplers.data()));
  }
}

/// placeSpread: each point's cell of round r is r * shares + its stratum
/// modulo shares, drawn as Light::Sampler::place draws it; past the last
/// cell a point is not active and draws nothing. With the samplers
/// drawing themselves (inLanes false) too.
void checkSpread(bool avx2, bool inLanes) {
  const std::deque<Material> ms = materials();
  const std::vector<Case> cs = cases(45, 9, ms);
  const Light light = areaLight(); // 12 cells
  const Light::Sampler sampler(light);
  const int shares = 5, rounds = 3;
  static LightLanes lanes;
  lanes.clear();
  std::vector<Sampler> samplers;
  for (size_t i = 0; i < cs.size(); ++i) {
    lanes.add(static_cast<uint32_t>(i), cs[i].hit, spawnOrigins(cs[i].hit), cs[i].n, cs[i].v,
              cs[i].pigment, *cs[i].m);
    samplers.emplace_back(4, i, 0);
    samplers.back().lightStratum = static_cast<uint32_t>(i * 7 + 3);
  }
  std::vector<Sampler> reference = samplers;
  if (inLanes) {
    ASSERT_TRUE(loadSamplers(lanes, samplers.data()));
  }
  for (int round = 0; round < rounds; ++round) {
    detail::placeSpread(lanes, {0, lanes.count}, sampler, round, shares, samplers.data(),
                        inLanes, avx2);
    for (size_t j = 0; j < lanes.count; ++j) {
      const int k = round * shares + static_cast<int>(reference[j].lightStratum % shares);
      ASSERT_EQ(lanes.active[j], k < 12) << "lane " << j << ", round " << round;
      if (k >= 12) continue;
      double a, b;
      sampler.place(k / light.cols, k % light.cols, reference[j], a, b);
      EXPECT_SAME_BITS(lanes.ax[j], a);
      EXPECT_SAME_BITS(lanes.az[j], b);
    }
  }
  if (inLanes) storeSamplers(lanes, samplers.data());
  for (size_t j = 0; j < lanes.count; ++j) EXPECT_EQ(samplers[j].next(), reference[j].next());
}

TEST(LightLanes, ScalarSpread) {
  checkSpread(false, true);
  checkSpread(false, false);
}

TEST(LightLanes, Avx2Spread) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkSpread(true, true);
}

TEST(LightLanes, ScalarPlace) { checkPlace(false); }

TEST(LightLanes, Avx2Place) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkPlace(true);
}

TEST(LightLanes, ScalarAddLit) {
  checkAddLit(false, 1);
  checkAddLit(false, 3);
}

TEST(LightLanes, Avx2AddLit) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2";
  checkAddLit(true, 1);
  checkAddLit(true, 3);
}

// The highlight's power by squaring, for integer exponents up to
// Material::kMaxIntegerExponent, stays within 2^-42 of std::pow relative
// (1024 is ten squarings); past it, and for other exponents, it is std::pow.
TEST(SpecularPower, SquaringAgreesWithPow) {
  for (double e : {2.0, 37.0, 65.0, 128.0, 160.0, 777.0, 1024.0, 1025.0, 2.5}) {
    Finish f;
    f.exponent = e;
    const Material m = Material::prepare(f, 0, true);
    EXPECT_EQ(m.integerExponent >= 0, e <= Material::kMaxIntegerExponent && e == std::floor(e));
    for (double x : {0.999999, 0.99, 0.9, 0.7, 0.31}) {
      const double exact = std::pow(x, e);
      if (m.integerExponent < 0) {
        EXPECT_EQ(specularPower(x, m), exact) << e;
      } else {
        EXPECT_NEAR(specularPower(x, m), exact, 0x1p-42 * exact + 1e-300) << e << " " << x;
      }
    }
  }
}

} // namespace
} // namespace lray
