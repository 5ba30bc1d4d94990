// Pipeline: render. The per-pixel error estimate of adaptive sampling: the
// standard error of the pixel's mean, from the spread of its samples, per
// channel, relative to the square root of the pixel's brightness (noise is
// seen relative to it), times sqrt(2 / pi). That factor makes it the
// expected value of the estimate of Dammertz et al. 2010 (as in Cycles:
// how far the mean of the odd-numbered samples lies from the mean of all),
// which LRay used before: a threshold asks for the same noise. But this one
// rests on all of the samples (3 (n - 1) degrees of freedom, not one per
// channel), so a pixel neither stops early because its two halves agreed
// by chance nor samples on because they did not (measured on the bench
// scenes: bench/HISTORY.md, 2026-12-05, tenth session).
#pragma once

#include "math/color.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lray {

/// The variance of the mean of `count` samples whose values, less `shift`,
/// sum to `sum` and their squares to `squares` (per channel; 0 below two
/// samples). `shift` (any value near the samples, e.g. their first mean)
/// keeps the difference of the two sums from cancelling in float.
inline Color varianceOfMean(const Color &sum, const Color &squares, uint32_t count) {
  if (count < 2) return {};
  const double n = count;
  auto one = [n](double s, double q) { return std::max(0.0, q - s * s / n) / (n * (n - 1)); };
  return {one(sum.r, squares.r), one(sum.g, squares.g), one(sum.b, squares.b)};
}

/// The estimate for a pixel whose samples have the mean `mean` and whose
/// mean has the variance `variance` (varianceOfMean: 0 below two samples,
/// and so is the estimate).
inline double pixelError(const Color &mean, const Color &variance) {
  constexpr double kHalfNormalMean = 0.7978845608028654; // sqrt(2 / pi)
  const double spread = std::sqrt(variance.r) + std::sqrt(variance.g) + std::sqrt(variance.b);
  const double brightness = std::max(0.0, mean.r + mean.g + mean.b);
  return kHalfNormalMean * spread / (1e-4 + std::sqrt(brightness));
}

} // namespace lray
