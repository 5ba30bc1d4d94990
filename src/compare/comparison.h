// lray-compare: one image against its approved version, by one metric
// (README.md, "Reference-image CI for your scenes"):
//   pixel  every channel within `threshold` (default 0.004, one 8-bit
//          step), except at most `allowed` % of the pixels
//   psnr   PSNR (peak 1) at least `threshold` dB (default 40)
//   ssim   mean SSIM (compare/ssim.h) at least `threshold` (default 0.99)
//   noise  the noise-aware test (compare/noise_test.h) at false-alarm
//          rate `threshold` (default 0.01), on EXR files with their
//          variance, or on two new renders at other seeds
// Whatever the metric, a non-finite pixel in the new image, or images of
// two sizes, fail. RMSE, PSNR, the largest difference and SSIM are always
// measured and reported.
#pragma once

#include "compare/compare_image.h"

#include <optional>
#include <string>
#include <vector>

namespace lray::compare {

enum class Metric { Pixel, Psnr, Ssim, Noise };

/// "pixel", "psnr", "ssim", "noise"; parseMetric returns nullopt for others.
const char *metricName(Metric m);
std::optional<Metric> parseMetric(const std::string &name);

struct Criteria {
  Metric metric = Metric::Pixel;
  std::optional<double> threshold; ///< the metric's default when empty
  double allowedPercent = 0;       ///< pixel: the share of pixels that may differ
  double thresholdOrDefault() const;
};

/// Why a criteria value is unusable ("" when fine): a tolerance < 0,
/// alpha outside (0, 1), SSIM above 1, ...
std::string criteriaProblem(const Criteria &c);

struct Outcome {
  bool pass = false;
  std::string verdict; ///< one line: the metric's figure against its bound
  double maxDifference = 0;
  int maxX = 0, maxY = 0;
  double rmse = 0, psnr = 0, ssim = 1, failingPercent = 0;
  size_t nonFinite = 0;
  size_t noiseTests = 0, noiseRejected = 0;
  double noiseMinP = 1;
  /// Per pixel, how far it differs (the largest channel difference, or
  /// |t| for the noise test), for the heat map; `heatScale` maps it to full
  /// brightness; `flagged` marks the pixels counted as failing.
  std::vector<float> heat;
  float heatScale = 1;
  std::vector<unsigned char> flagged;
};

/// `second`, for the noise test of images without variance: another
/// render of the new image at another seed (noise_test.h, varianceFromPair).
Outcome compareImages(const CompareImage &fresh, const CompareImage &approved,
                      const Criteria &criteria, const CompareImage *second = nullptr);

} // namespace lray::compare
