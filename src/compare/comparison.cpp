#include "compare/comparison.h"

#include "compare/noise_test.h"
#include "compare/ssim.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace lray::compare {

const char *metricName(Metric m) {
  switch (m) {
  case Metric::Pixel:
    return "pixel";
  case Metric::Psnr:
    return "psnr";
  case Metric::Ssim:
    return "ssim";
  case Metric::Noise:
    return "noise";
  }
  return "?";
}

std::optional<Metric> parseMetric(const std::string &name) {
  for (Metric m : {Metric::Pixel, Metric::Psnr, Metric::Ssim, Metric::Noise})
    if (name == metricName(m)) return m;
  return std::nullopt;
}

double Criteria::thresholdOrDefault() const {
  if (threshold) return *threshold;
  switch (metric) {
  case Metric::Pixel:
    return 0.004;
  case Metric::Psnr:
    return 40;
  case Metric::Ssim:
    return 0.99;
  case Metric::Noise:
    return 0.01;
  }
  return 0;
}

std::string criteriaProblem(const Criteria &c) {
  const double t = c.thresholdOrDefault();
  if (!std::isfinite(t)) return "the threshold must be a finite number";
  if (!(c.allowedPercent >= 0 && c.allowedPercent <= 100))
    return fmt::format("the allowed share of differing pixels must be 0 to 100 %, not {}",
                       c.allowedPercent);
  switch (c.metric) {
  case Metric::Pixel:
    if (t < 0) return fmt::format("the pixel tolerance must be >= 0, not {}", t);
    break;
  case Metric::Psnr:
    break;
  case Metric::Ssim:
    if (t > 1) return fmt::format("an SSIM bound above 1 fails every image ({})", t);
    break;
  case Metric::Noise:
    if (!(t > 0 && t < 1))
      return fmt::format("the noise test's false-alarm rate must lie in (0, 1), not {}", t);
    break;
  }
  return "";
}

Outcome compareImages(const CompareImage &fresh, const CompareImage &approved,
                      const Criteria &criteria, const CompareImage *second) {
  if (fresh.width != approved.width || fresh.height != approved.height)
    throw CompareError(fmt::format("the new image is {} x {}, the approved one {} x {}",
                                   fresh.width, fresh.height, approved.width, approved.height));
  const double bound = criteria.thresholdOrDefault();
  const size_t n = fresh.pixels();
  Outcome o;
  o.heat.assign(n, 0.f);
  o.flagged.assign(n, 0);
  double squares = 0;
  size_t failing = 0;
  std::vector<size_t> notFinite;
  const double tolerance = criteria.metric == Metric::Pixel ? bound : 0.004;
  for (size_t i = 0; i < n; ++i) {
    float most = 0;
    bool finite = true;
    for (int c = 0; c < 3; ++c) {
      const float a = fresh.rgb[i * 3 + c], b = approved.rgb[i * 3 + c];
      if (!std::isfinite(a)) finite = false;
      const double diff = std::abs(static_cast<double>(a) - b);
      if (std::isfinite(diff)) squares += diff * diff;
      most = std::max(most, static_cast<float>(diff));
    }
    if (!finite) {
      notFinite.push_back(i);
      most = HUGE_VALF;
    }
    o.heat[i] = most;
    if (most > tolerance || !finite) {
      ++failing;
      if (criteria.metric == Metric::Pixel) o.flagged[i] = 1;
    }
    if (most > o.maxDifference) {
      o.maxDifference = most;
      o.maxX = static_cast<int>(i % static_cast<size_t>(fresh.width));
      o.maxY = static_cast<int>(i / static_cast<size_t>(fresh.width));
    }
  }
  o.rmse = std::sqrt(squares / (3.0 * static_cast<double>(n)));
  o.psnr = o.rmse > 0 ? -20 * std::log10(o.rmse) : HUGE_VAL;
  o.failingPercent = 100.0 * static_cast<double>(failing) / static_cast<double>(n);
  o.ssim = ssim(fresh, approved).mean;
  o.heatScale = static_cast<float>(std::max(4 * tolerance, 1e-6));

  std::string figure;
  switch (criteria.metric) {
  case Metric::Pixel:
    o.pass = o.failingPercent <= criteria.allowedPercent;
    figure = fmt::format("{:.4g} % of pixels differ by more than {} (allowed {} %), largest "
                         "{:.4g} at ({}, {})",
                         o.failingPercent, bound, criteria.allowedPercent, o.maxDifference, o.maxX,
                         o.maxY);
    break;
  case Metric::Psnr:
    o.pass = o.psnr >= bound;
    figure = fmt::format("PSNR {:.2f} dB (at least {} dB)", o.psnr, bound);
    break;
  case Metric::Ssim:
    o.pass = o.ssim >= bound;
    figure = fmt::format("SSIM {:.5f} (at least {})", o.ssim, bound);
    break;
  case Metric::Noise: {
    NoiseTestResult t;
    if (second) {
      CompareImage mean, reference = approved;
      varianceFromPair(fresh, *second, reference, std::max(fresh.quantum, approved.quantum), mean);
      t = noiseTest(mean, reference, bound);
    } else {
      t = noiseTest(fresh, approved, bound);
    }
    o.pass = t.rejected == 0;
    o.noiseTests = t.tests;
    o.noiseRejected = t.rejected;
    o.noiseMinP = t.minP;
    o.heat = t.t;
    o.flagged = t.flagged;
    o.heatScale = 8; // |t| of 8 is far beyond noise
    figure = fmt::format("{} of {} tests beyond the noise at false-alarm rate {} (Holm); ",
                         t.rejected, t.tests, bound);
    figure += t.minP < 1 ? fmt::format("smallest p {:.3g} over a {}x{} block at ({}, {})", t.minP,
                                       t.worstBlock, t.worstBlock, t.worstX, t.worstY)
                         : fmt::format("every p above {}", bound);
    break;
  }
  }
  o.nonFinite = notFinite.size();
  if (o.nonFinite) {
    o.pass = false;
    figure = fmt::format("{} pixels are not finite (NaN or infinite); ", o.nonFinite) + figure;
    for (size_t i : notFinite) {
      o.flagged[i] = 1;
      o.heat[i] = HUGE_VALF;
    }
  }
  o.verdict = fmt::format("{}: {}; RMSE {:.3g}, PSNR {:.2f} dB, SSIM {:.4f}",
                          metricName(criteria.metric), figure, o.rmse, o.psnr, o.ssim);
  return o;
}

} // namespace lray::compare
