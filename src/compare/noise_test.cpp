#include "compare/noise_test.h"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>

namespace lray::compare {

namespace {

/// The largest block whose failure marks its pixels in `flagged`.
constexpr int kMarkedBlock = 8;

/// R, G, B and their sum.
constexpr int kChannels = 4;

/// One test: a block's mean difference in one channel.
struct Test {
  double p;
  int block, x, y;
};

/// A variance floor per pixel: float rounding of the stored values (two
/// renders of a noise-free pixel may differ in the last bits of a float).
double roundingVariance(double a, double b) {
  const double ulp = 2e-7 * std::max({std::abs(a), std::abs(b), 1e-6});
  return ulp * ulp;
}

} // namespace

void varianceFromPair(const CompareImage &a, const CompareImage &b, CompareImage &approved,
                      double quantum, CompareImage &fresh) {
  if (a.width != b.width || a.height != b.height || a.width != approved.width ||
      a.height != approved.height)
    throw CompareError("the two new renders and the approved image differ in size");
  const size_t n = a.pixels();
  const double rounding = quantum * quantum / 12;
  fresh = CompareImage{};
  fresh.width = a.width;
  fresh.height = a.height;
  fresh.rgb.resize(n * 3);
  fresh.variance.resize(n * 3);
  fresh.samples.assign(n, 2.f); // one degree of freedom
  approved.variance.resize(n * 3);
  approved.samples.assign(n, 2.f);
  for (size_t k = 0; k < n * 3; ++k) {
    const double d = static_cast<double>(a.rgb[k]) - b.rgb[k];
    // One render's variance: E[(a - b)^2] / 2; the mean of two has half.
    const double one = d * d / 2 + rounding;
    fresh.rgb[k] = static_cast<float>((static_cast<double>(a.rgb[k]) + b.rgb[k]) / 2);
    fresh.variance[k] = static_cast<float>(one / 2);
    approved.variance[k] = static_cast<float>(one);
  }
}

double twoSidedP(double t, double dof) {
  t = std::abs(t);
  if (!(t > 0)) return 1;
  if (std::isinf(t)) return 0;
  if (dof > 1e6) {
    return 2 * boost::math::cdf(boost::math::complement(boost::math::normal(), t));
  }
  return 2 * boost::math::cdf(boost::math::complement(boost::math::students_t(dof), t));
}

NoiseTestResult noiseTest(const CompareImage &fresh, const CompareImage &approved, double alpha) {
  if (!fresh.hasVariance() || !approved.hasVariance())
    throw CompareError("the noise test needs each pixel's variance: EXR files written by lray "
                       "(-f exr), which hold Variance.R/G/B and SampleCount, or a second new "
                       "render at another seed (--second, or second_seed in a suite)");
  const int w = fresh.width, h = fresh.height;
  const size_t n = fresh.pixels();
  // Per pixel and channel: difference d, its variance v, and v^2/dof summed
  // for Welch-Satterthwaite. Channel 3 is the sum of R, G and B (a change
  // of a grey light shows in all three); its variance is bounded by
  // (sum of the channels' standard deviations)^2, whatever their
  // correlation (exact for a grey picture), since a pixel's channels come
  // from the same samples.
  std::vector<double> d(n * kChannels), v(n * kChannels), q(n * kChannels);
  auto dofOf = [](const CompareImage &im, size_t i) {
    return im.samples.empty() ? 1e9 : std::max(1.0, static_cast<double>(im.samples[i]) - 1);
  };
  for (size_t i = 0; i < n; ++i) {
    const double dofA = dofOf(fresh, i), dofB = dofOf(approved, i);
    double sumD = 0, sumFloor = 0, sdA = 0, sdB = 0;
    for (int c = 0; c < 3; ++c) {
      const size_t k = i * 3 + c, m = i * kChannels + c;
      const double a = fresh.rgb[k], b = approved.rgb[k];
      const double va = std::max(0.f, fresh.variance[k]), vb = std::max(0.f, approved.variance[k]);
      const double floor = roundingVariance(a, b);
      d[m] = a - b;
      v[m] = va + vb + floor;
      q[m] = va * va / dofA + vb * vb / dofB + floor * floor / 1e9;
      sumD += d[m];
      sumFloor += floor;
      sdA += std::sqrt(va);
      sdB += std::sqrt(vb);
    }
    const size_t m = i * kChannels + 3;
    d[m] = sumD;
    v[m] = sdA * sdA + sdB * sdB + sumFloor;
    q[m] = sdA * sdA * sdA * sdA / dofA + sdB * sdB * sdB * sdB / dofB + sumFloor * sumFloor / 1e9;
  }
  // A test is worth its p-value only where it could be rejected: Holm's
  // thresholds are all at most alpha, and Student's t is wider than the
  // normal, so a normal p above alpha is never rejected.
  const double zCut = std::abs(boost::math::quantile(boost::math::normal(), alpha / 2));
  std::vector<Test> candidates;
  NoiseTestResult result;
  result.t.assign(n, 0.f);
  result.flagged.assign(n, 0);
  for (int block = 1;; block *= 2) {
    const int bw = (w + block - 1) / block, bh = (h + block - 1) / block;
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx)
        for (int c = 0; c < kChannels; ++c) {
          double sd = 0, sv = 0, sq = 0;
          for (int y = by * block; y < std::min(h, (by + 1) * block); ++y)
            for (int x = bx * block; x < std::min(w, (bx + 1) * block); ++x) {
              const size_t k = (static_cast<size_t>(y) * w + x) * kChannels + c;
              sd += d[k];
              sv += v[k];
              sq += q[k];
            }
          ++result.tests;
          // The block mean's difference over its standard deviation (the
          // 1/count factors cancel; Satterthwaite's dof too).
          const double t = sv > 0 ? sd / std::sqrt(sv) : sd == 0 ? 0 : HUGE_VAL;
          if (block == 1) {
            float &heat = result.t[static_cast<size_t>(by) * w + bx];
            heat = std::max(heat, static_cast<float>(std::min(std::abs(t), 1e30)));
          }
          if (std::isnan(sd)) {
            candidates.push_back({0, block, bx * block, by * block});
          } else if (std::abs(t) > zCut) {
            const double dof = sq > 0 ? sv * sv / sq : 1e9;
            candidates.push_back({twoSidedP(t, dof), block, bx * block, by * block});
          }
        }
    if (block >= w && block >= h) break;
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Test &a, const Test &b) { return a.p < b.p; });
  if (!candidates.empty()) {
    result.minP = candidates.front().p;
    result.worstBlock = candidates.front().block;
    result.worstX = candidates.front().x;
    result.worstY = candidates.front().y;
  }
  // Holm: the k-th smallest p (from 0) is rejected while p <= alpha / (m - k).
  for (size_t k = 0; k < candidates.size(); ++k) {
    const Test &t = candidates[k];
    if (t.p > alpha / static_cast<double>(result.tests - k)) break;
    ++result.rejected;
    if (t.block > kMarkedBlock) continue; // the figures tell; the map would turn all cyan
    for (int y = t.y; y < std::min(h, t.y + t.block); ++y)
      for (int x = t.x; x < std::min(w, t.x + t.block); ++x)
        result.flagged[static_cast<size_t>(y) * w + x] = 1;
  }
  return result;
}

} // namespace lray::compare
