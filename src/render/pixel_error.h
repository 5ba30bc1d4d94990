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
// scenes: bench/HISTORY.md, 2026-12-05, tenth session). The Whitted
// integrator's samples are stratified, and their estimate is lowered by the
// rate at which that makes the error fall (pixelError with
// SampleSet::Stratified; lua/README.md, "Pixel sampling").
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

/// What a pixel's samples are, for its error estimate.
enum class SampleSet {
  /// Taken as independent: the path tracer's, whose bounces' many
  /// dimensions gain little from the stratification (measured on the
  /// Cornell box: its true error over the spread's estimate does not fall
  /// from 4 to 64 samples).
  Independent,
  /// One Owen-scrambled Sobol set over the pixel (and the lens and the
  /// shutter), as the Whitted integrator takes them.
  Stratified,
};

/// How much lower than their spread says the error of the mean of `count`
/// stratified samples is taken to be: (count / 4)^(-1/4) from 4 samples
/// on (centre-first sampling's first Sobol pass), 1 below. The error of
/// independent samples falls as n^(-1/2); that of scrambled Sobol samples
/// falls as n^(-3/4) where an edge crosses the pixel (Owen 1997: variance
/// O(n^(-3/2)) for an integrand with a jump along a curve) and faster
/// where the pixel is smooth: the slowest rate in a picture, which every
/// part of it reaches. Measured on the bench scenes (glass, pigments, an area light):
/// the true error over the samples' estimate falls by 0.55-0.69 per 4x the
/// samples, against this factor's 0.71, so the estimate stays above the
/// true error, by less as samples are added.
inline double stratifiedErrorFactor(uint32_t count) {
  return count > 4 ? std::sqrt(std::sqrt(4.0 / count)) : 1.0;
}

/// The estimate for a pixel of `count` samples of the kind `samples`, as
/// adaptive sampling and the film's Error channel take it.
inline double pixelError(const Color &mean, const Color &variance, uint32_t count,
                         SampleSet samples) {
  const double e = pixelError(mean, variance);
  return samples == SampleSet::Stratified ? e * stratifiedErrorFactor(count) : e;
}

} // namespace lray
