// Pipeline: render. The per-pixel error estimate of adaptive sampling
// (Dammertz et al. 2010, "A Hierarchical Automatic Stopping Condition for
// Monte Carlo Global Illumination"; Cycles uses the same): a pixel's samples
// are split into two interleaved halves, and the estimate is how far the
// mean of the odd-numbered half lies from the mean of all, relative to the
// square root of the pixel's brightness (noise is seen relative to it).
#pragma once

#include "math/color.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lray {

/// The estimate for a pixel whose `count` samples sum to `sum`, the
/// odd-numbered ones (1, 3, 5, ...) to `oddSum`; 0 below two samples.
inline double pixelError(const Color &sum, const Color &oddSum, uint32_t count) {
  if (count < 2) return 0;
  const Color all = sum / static_cast<double>(count);
  const Color odd = oddSum / static_cast<double>(count / 2);
  const double difference =
      std::abs(all.r - odd.r) + std::abs(all.g - odd.g) + std::abs(all.b - odd.b);
  const double brightness = std::max(0.0, all.r + all.g + all.b);
  return difference / (1e-4 + std::sqrt(brightness));
}

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

} // namespace lray
