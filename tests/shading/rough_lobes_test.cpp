// The rough reflection and refraction lobes evaluated for a pair of
// directions (shading/rough_lobes.h), against the sampling they must match
// (shading/specular_lobes.h, as the path tracer chooses between its two
// lobes): every sampled direction carries fcos / pdf, the density
// integrates to the share of samples that leave the surface, and samples
// follow it (chi-square over the whole sphere, reflection and refraction);
// and the diffuse lobe's cosine-weighted directions against their density.
#include "math/onb.h"
#include "shading/cosine_lobe.h"
#include "shading/distribution_checks.h"
#include "shading/rough_lobes.h"
#include "shading/specular_lobes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace lray {
namespace {

constexpr double kPi = std::numbers::pi;

struct Case {
  double alpha, theta, eta, reflection, refraction;
  bool fresnel;
  std::string name() const {
    return "alpha " + std::to_string(alpha) + " theta " + std::to_string(theta) + " eta " +
           std::to_string(eta) + " kr " + std::to_string(reflection) + " kt " +
           std::to_string(refraction) + (fresnel ? " fresnel" : "");
  }
  Finish finish() const {
    Finish f;
    f.reflection = reflection;
    f.refraction = refraction;
    f.roughness = alpha;
    f.fresnel = fresnel;
    return f;
  }
  Vec3 wo() const { return Vec3(std::sin(theta) * 0.6, std::sin(theta) * 0.8, std::cos(theta)); }
};

std::vector<Case> cases() {
  std::vector<Case> all;
  for (double alpha : {0.15, 0.5, 0.9})
    for (double theta : {0.3, 1.2})
      for (double eta : {1 / 1.5, 1.5}) {
        all.push_back({alpha, theta, eta, 1, 1, true});
        all.push_back({alpha, theta, eta, 0.6, 0.3, false});
      }
  all.push_back({0.3, 0.8, 1.33, 0, 1, false}); // refraction alone, total internal reflection
  all.push_back({0.3, 0.8, 1 / 1.33, 0.7, 0, true});
  return all;
}

/// One sample as the path tracer draws it once it has chosen these lobes:
/// a visible microfacet, then reflection or refraction by their weights
/// about it (u). `carried` is what it multiplies the throughput by.
struct Drawn {
  Vec3 wi;
  double carried = 0;
  bool through = false;
};
Drawn draw(const Case &c, Sampler &sampler) {
  const Vec3 n(0, 0, 1), dir = -c.wo();
  const Finish f = c.finish();
  const SpecularLobes l = specularLobes(dir, n, f, true, true, c.eta, sampler);
  const double u = sampler.next(), sum = l.kr + l.kt;
  Drawn d;
  if (!(sum > 0)) return d;
  d.through = u * sum >= l.kr && !l.totalInternal;
  d.wi = d.through ? l.refracted : l.mirror;
  d.carried = sum * l.throughput(n, dir, d.wi, d.through);
  return d;
}

TEST(RoughLobes, ASampledDirectionCarriesItsValueOverItsDensity) {
  for (const Case &c : cases()) {
    SCOPED_TRACE(c.name());
    const RoughLobes lobes(c.finish(), true, true, c.eta);
    Sampler sampler(3, 5, 7);
    int reflected = 0, refracted = 0;
    for (int k = 0; k < 4000; ++k) {
      const Drawn d = draw(c, sampler);
      if (!(d.carried > 0)) continue;
      const RoughLobes::Value v = lobes.evaluate({0, 0, 1}, c.wo(), d.wi);
      ASSERT_GT(v.pdf, 0) << k;
      ASSERT_NEAR(v.fcos / v.pdf, d.carried, 1e-9 * d.carried) << k;
      (d.through ? refracted : reflected) += 1;
    }
    EXPECT_EQ(reflected > 0, c.reflection > 0 || c.eta > 1); // inside: total internal reflection
    EXPECT_EQ(refracted > 0, c.refraction > 0);
  }
}

/// The integral of g over the whole sphere (two hemispheres by quadrature).
template <class F> double sphere(F g) {
  return testing::hemisphere(g) + testing::hemisphere([&](const Vec3 &w) {
           return g(Vec3(w.x, w.y, -w.z));
         });
}

TEST(RoughLobes, TheDensityIntegratesToTheShareOfSamplesThatLeave) {
  // A sample the microfacets shadow (sent under the surface by a
  // reflection, over it by a refraction) is lost: the density of the rest
  // integrates to their share. The value over the sphere is the lobes'
  // albedo, which sampling must give too.
  for (const Case &c : cases()) {
    if (c.alpha < 0.5) continue; // narrow lobes need a finer quadrature than a test affords
    SCOPED_TRACE(c.name());
    const RoughLobes lobes(c.finish(), true, true, c.eta);
    constexpr int kSamples = 200000;
    Sampler sampler(11, 13, 17);
    double kept = 0, albedo = 0;
    for (int k = 0; k < kSamples; ++k) {
      const Drawn d = draw(c, sampler);
      kept += d.carried > 0;
      albedo += d.carried;
    }
    const Vec3 n(0, 0, 1), wo = c.wo();
    EXPECT_NEAR(sphere([&](const Vec3 &wi) { return lobes.evaluate(n, wo, wi).pdf; }),
                kept / kSamples, 5e-3);
    EXPECT_NEAR(sphere([&](const Vec3 &wi) { return lobes.evaluate(n, wo, wi).fcos; }),
                albedo / kSamples, 5e-3);
  }
}

TEST(RoughLobes, SamplesFollowTheirDensityOverTheSphere) {
  // Bins in cos theta (uniform over [-1, 1]: reflection above, refraction
  // below) and phi; the expected counts integrate the density over each.
  constexpr int kZ = 24, kPhi = 24, kSub = 20, kSamples = 300000;
  for (const Case &c : cases()) {
    SCOPED_TRACE(c.name());
    const RoughLobes lobes(c.finish(), true, true, c.eta);
    auto bin = [&](const Vec3 &w) {
      double phi = std::atan2(w.y, w.x);
      if (phi < 0) phi += 2 * kPi;
      const int i = std::clamp(int((w.z + 1) / 2 * kZ), 0, kZ - 1);
      const int j = std::min(kPhi - 1, int(phi / (2 * kPi) * kPhi));
      return i * kPhi + j;
    };
    std::vector<double> observed(kZ * kPhi + 1, 0), expected(kZ * kPhi + 1, 0);
    Sampler sampler(19, 23, 29);
    for (int k = 0; k < kSamples; ++k) {
      const Drawn d = draw(c, sampler);
      observed[d.carried > 0 ? bin(d.wi) : kZ * kPhi] += 1; // the last bin: lost samples
    }
    const Vec3 n(0, 0, 1), wo = c.wo();
    double inside = 0;
    for (int i = 0; i < kZ; ++i)
      for (int j = 0; j < kPhi; ++j)
        for (int a = 0; a < kSub; ++a)
          for (int b = 0; b < kSub; ++b) {
            const double z = -1 + 2 * (i + (a + 0.5) / kSub) / kZ, r = std::sqrt(1 - z * z);
            const double phi = 2 * kPi * (j + (b + 0.5) / kSub) / kPhi;
            const double area = 2.0 / (kZ * kSub) * 2 * kPi / (kPhi * kSub);
            const double p = lobes.evaluate(n, wo, {r * std::cos(phi), r * std::sin(phi), z}).pdf;
            expected[i * kPhi + j] += p * area * kSamples;
            inside += p * area;
          }
    expected[kZ * kPhi] = std::max(0.0, 1 - inside) * kSamples;
    EXPECT_LT(testing::chiSquareRatio(observed, expected), 1);
  }
}

TEST(CosineLobe, SamplesFollowTheirDensity) {
  // The diffuse lobe's directions against cos / pi, about a tilted normal
  // (the basis it is carried into must not bend them), binned in the
  // normal's own frame; the density integrates to one.
  constexpr int kTheta = 16, kPhi = 24, kSub = 10, kSamples = 200000;
  const Vec3 n = normalize(Vec3(0.3, -0.5, 0.8));
  Vec3 t, b;
  orthonormalBasis(n, t, b);
  auto bin = [&](const Vec3 &w) {
    const double z = dot(w, n);
    double phi = std::atan2(dot(w, b), dot(w, t));
    if (phi < 0) phi += 2 * kPi;
    const int i = std::clamp(int(z * kTheta), 0, kTheta - 1);
    const int j = std::min(kPhi - 1, int(phi / (2 * kPi) * kPhi));
    return i * kPhi + j;
  };
  std::vector<double> observed(kTheta * kPhi, 0), expected(kTheta * kPhi, 0);
  Sampler sampler(31, 37, 41);
  for (int k = 0; k < kSamples; ++k) {
    double u1, u2, c;
    sampler.next2D(u1, u2);
    const Vec3 w = sampleCosine(n, u1, u2, c);
    ASSERT_NEAR(c, dot(w, n), 1e-12);
    ASSERT_NEAR(length(w), 1, 1e-12);
    observed[bin(w)] += 1;
  }
  double total = 0;
  for (int i = 0; i < kTheta; ++i)
    for (int j = 0; j < kPhi; ++j)
      for (int a = 0; a < kSub; ++a) {
        const double z = (i + (a + 0.5) / kSub) / kTheta; // cos theta, uniform: dA = dz dphi
        const double p = cosinePdf(z) * (1.0 / (kTheta * kSub)) * (2 * kPi / kPhi);
        expected[i * kPhi + j] += p * kSamples;
        total += p;
      }
  EXPECT_NEAR(total, 1, 1e-6);
  EXPECT_LT(testing::chiSquareRatio(observed, expected), 1);
}

TEST(RoughLobes, NothingForDirectionsNoMicrofacetConnects) {
  Finish f;
  f.reflection = 1;
  f.roughness = 0.4;
  const RoughLobes mirrorOnly(f, true, false, 1.0);
  const Vec3 n(0, 0, 1), wo = normalize(Vec3(0.3, 0, 1));
  const RoughLobes::Value below = mirrorOnly.evaluate(n, wo, normalize(Vec3(0.2, 0.1, -1)));
  EXPECT_EQ(below.fcos, 0); // no refraction lobe
  EXPECT_EQ(below.pdf, 0);
  const RoughLobes::Value above = mirrorOnly.evaluate(n, wo, normalize(Vec3(-0.3, 0, 1)));
  EXPECT_GT(above.fcos, 0);
  EXPECT_EQ(mirrorOnly.evaluate(n, -wo, wo).pdf, 0); // wo under the surface
}

} // namespace
} // namespace lray
