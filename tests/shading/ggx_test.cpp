// The GGX microfacet distribution of rough finishes (shading/ggx.h) and the
// lobes built on it (shading/specular_lobes.h), checked as Mitsuba's and
// pbrt-v4's BSDF tests do: the distribution and the visible-normal density
// integrate to one, samples follow that density (a chi-square test), and
// the reflection lobe's throughput agrees with the BRDF it samples and
// never returns more energy than it receives.
#include "shading/ggx.h"
#include "shading/specular_lobes.h"
#include "shading/distribution_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace lray {
namespace {

using testing::chiSquareRatio;
using testing::hemisphere;
constexpr double kPi = std::numbers::pi;

Vec3 direction(double theta, double phi = 0.3) {
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

TEST(Ggx, ProjectedNormalsIntegrateToOne) {
  for (double alpha : {0.05, 0.2, 0.5, 1.0}) {
    SCOPED_TRACE(alpha);
    EXPECT_NEAR(hemisphere([&](const Vec3 &m) { return ggx::density(m.z, alpha) * m.z; }), 1,
                2e-3);
  }
}

TEST(Ggx, VisibleNormalDensityIntegratesToOne) {
  for (double alpha : {0.05, 0.3, 1.0})
    for (double theta : {0.0, 0.8, 1.4}) {
      SCOPED_TRACE(std::to_string(alpha) + " at " + std::to_string(theta));
      const Vec3 wo = direction(theta);
      EXPECT_NEAR(
          hemisphere([&](const Vec3 &m) { return ggx::visibleNormalPdf(wo, m, alpha); }), 1,
          3e-3);
    }
}

TEST(Ggx, VisibleNormalSamplesFollowTheirDensity) {
  constexpr int kTheta = 16, kPhi = 24, kSamples = 400000;
  for (double alpha : {0.1, 0.4, 0.9})
    for (double theta : {0.0, 0.7, 1.3}) {
      SCOPED_TRACE(std::to_string(alpha) + " at " + std::to_string(theta));
      const Vec3 wo = direction(theta, 1.1);
      // Bins in cos theta of the microfacet normal (squared, to resolve the
      // peak) and phi.
      auto bin = [&](const Vec3 &m) {
        const double x = std::sqrt(std::clamp(1 - m.z, 0.0, 1.0));
        double phi = std::atan2(m.y, m.x);
        if (phi < 0) phi += 2 * kPi;
        const int i = std::min(kTheta - 1, int(x * kTheta));
        const int j = std::min(kPhi - 1, int(phi / (2 * kPi) * kPhi));
        return i * kPhi + j;
      };
      std::vector<double> observed(kTheta * kPhi, 0), expected(kTheta * kPhi, 0);
      Sampler sampler(7, 11, 13);
      for (int k = 0; k < kSamples; ++k) {
        const double u1 = sampler.next(), u2 = sampler.next();
        observed[bin(ggx::sampleVisibleNormalLocal(wo, alpha, u1, u2))] += 1;
      }
      // The expected counts: the density integrated over each bin.
      constexpr int kSub = 12;
      for (int i = 0; i < kTheta; ++i)
        for (int j = 0; j < kPhi; ++j)
          for (int a = 0; a < kSub; ++a)
            for (int b = 0; b < kSub; ++b) {
              const double x = (i + (a + 0.5) / kSub) / kTheta, cosT = 1 - x * x;
              const double sinT = std::sqrt(1 - cosT * cosT);
              const double phi = 2 * kPi * (j + (b + 0.5) / kSub) / kPhi;
              const Vec3 m(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
              const double area = 2 * x / (kTheta * kSub) * 2 * kPi / (kPhi * kSub);
              expected[i * kPhi + j] += ggx::visibleNormalPdf(wo, m, alpha) * area * kSamples;
            }
      EXPECT_LT(chiSquareRatio(observed, expected), 1);
    }
}

/// The reflection lobe's mean throughput from wo (its albedo) by sampling
/// it as the integrators do.
double sampledAlbedo(const Vec3 &wo, double alpha, int samples) {
  Finish f;
  f.reflection = 1;
  f.roughness = alpha;
  const Vec3 n(0, 0, 1), dir = -wo;
  Sampler sampler(1, 2, 3);
  double sum = 0;
  for (int k = 0; k < samples; ++k) {
    const SpecularLobes l = specularLobes(dir, n, f, true, false, 1.0, sampler);
    sum += l.kr * l.throughput(n, dir, l.mirror, false);
  }
  return sum / samples;
}

TEST(Ggx, ReflectionThroughputMatchesTheBrdfItSamples) {
  // The BRDF D G2 / (4 cos_o cos_i) times cos_i, integrated over incoming
  // directions, against the mean of what sampling by visible normals
  // carries: the two must agree (a wrong Jacobian or G would not).
  for (double alpha : {0.1, 0.5, 1.0})
    for (double theta : {0.2, 1.0, 1.4}) {
      SCOPED_TRACE(std::to_string(alpha) + " at " + std::to_string(theta));
      const Vec3 wo = direction(theta);
      const double brdf = hemisphere([&](const Vec3 &wi) {
        const Vec3 h = normalize(wo + wi);
        const double lo = ggx::lambda(wo.z, alpha), li = ggx::lambda(wi.z, alpha);
        return ggx::density(h.z, alpha) / (1 + lo + li) / (4 * wo.z);
      });
      EXPECT_NEAR(sampledAlbedo(wo, alpha, 200000), brdf, 5e-3);
    }
}

TEST(Ggx, ReflectionNeverReturnsMoreThanItReceives) {
  for (double alpha : {0.01, 0.05, 0.2, 0.5, 0.8, 1.0})
    for (double theta : {0.0, 0.5, 1.0, 1.3, 1.5}) {
      SCOPED_TRACE(std::to_string(alpha) + " at " + std::to_string(theta));
      const double albedo = sampledAlbedo(direction(theta), alpha, 20000);
      EXPECT_LE(albedo, 1.0);
      EXPECT_GT(albedo, alpha <= 0.05 && theta < 1.2 ? 0.99 : 0.3); // lost: shadowed facets only
    }
}

TEST(Ggx, SmoothLobesDrawNoSampleAndKeepTheMirror) {
  Finish f;
  f.reflection = 0.5;
  f.refraction = 0.5;
  f.refractionIndex = 1.5;
  Sampler a(1, 2, 3), b(1, 2, 3);
  const Vec3 n(0, 0, 1), dir = normalize(Vec3(1, 0, -1));
  const SpecularLobes l = specularLobes(dir, n, f, true, true, 1 / 1.5, a);
  EXPECT_FALSE(l.rough);
  EXPECT_EQ(a.next(), b.next()) << "a smooth finish must not draw from the sampler";
  EXPECT_NEAR(l.mirror.x, dir.x, 1e-15);
  EXPECT_NEAR(l.mirror.z, -dir.z, 1e-15);
  EXPECT_DOUBLE_EQ(l.throughput(n, dir, l.mirror, false), 1);
}

TEST(Ggx, RoughRefractionLeavesThroughTheSurface) {
  Finish f;
  f.refraction = 1;
  f.refractionIndex = 1.5;
  f.roughness = 0.5;
  Sampler sampler(4, 5, 6);
  const Vec3 n(0, 0, 1), dir = normalize(Vec3(0.6, 0, -0.8));
  double mean = 0;
  for (int k = 0; k < 20000; ++k) {
    const SpecularLobes l = specularLobes(dir, n, f, false, true, 1 / 1.5, sampler);
    ASSERT_FALSE(l.totalInternal); // entering glass: never
    const double t = l.throughput(n, dir, l.refracted, true);
    EXPECT_GE(t, 0);
    EXPECT_LE(t, 1);
    if (t > 0) {
      EXPECT_LT(dot(l.refracted, n), 0);
    }
    mean += t / 20000;
  }
  EXPECT_GT(mean, 0.85); // a little is lost to shadowed microfacets
  EXPECT_LE(mean, 1);
}

} // namespace
} // namespace lray
