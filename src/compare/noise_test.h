// lray-compare: the noise-aware test for Monte Carlo renders. Two renders
// of the same picture with independent samples differ by noise; this test
// asks whether they differ by more than that noise explains.
//
// Each pixel value is the mean of its samples, with a variance known from
// them (lray's EXR Variance.R/G/B channels: the samples' variance over
// their count; a stratified render's true variance is lower, so the test
// errs on the side of passing). For each channel (and for R + G + B), the
// difference of the
// two images is tested (Welch's two-sample t-test, degrees of freedom by
// Welch-Satterthwaite from the sample counts) pixel by pixel and also over
// blocks of 2x2, 4x4, ... pixels up to the whole image, the blocks' means
// having their pixels' pooled variance: a small object missing shows at
// the pixel level, a 1 % change of a light over many pixels in the large
// blocks, where the noise averages away. All these tests together are one
// family: Holm-Bonferroni (1979) keeps the chance that any of them fails
// for two renders of one picture at most alpha, whatever their dependence
// (the blocks share pixels), and counts which ones fail. 8-bit files carry
// no variance: varianceFromPair estimates it from two new renders.
#pragma once

#include "compare/compare_image.h"

#include <cstddef>
#include <vector>

namespace lray::compare {

struct NoiseTestResult {
  size_t tests = 0;           ///< the size of the family
  size_t rejected = 0;        ///< tests Holm-Bonferroni rejects at alpha
  double minP = 1;            ///< the smallest p-value
  int worstBlock = 1;         ///< the block size (pixels per side) of the smallest p
  int worstX = 0, worstY = 0; ///< its top-left pixel
  /// Per pixel, the largest |t| of its channels at the pixel level (the
  /// heat map), and whether a rejected test of a block up to 8 x 8 covers
  /// it (larger blocks would mark most of the picture).
  std::vector<float> t;
  std::vector<unsigned char> flagged;
};

/// Tests `fresh` against `approved` at false-alarm rate `alpha`; both need
/// their variance (CompareError otherwise) and must be the same size.
NoiseTestResult noiseTest(const CompareImage &fresh, const CompareImage &approved, double alpha);

/// For images without variance (8-bit files): the new image as the mean of
/// two renders at other seeds, `a` and `b`, with each pixel's variance
/// estimated from their difference (one degree of freedom per pixel; the
/// blocks pool many), and `approved` given the variance of one render with
/// the same settings. `quantum` is the files' step (1/255 for 8 bits): its
/// rounding adds quantum^2/12 to each value's variance. Images must be the
/// same size.
void varianceFromPair(const CompareImage &a, const CompareImage &b, CompareImage &approved,
                      double quantum, CompareImage &fresh);

/// The two-sided p-value of Student's t with `dof` degrees of freedom
/// (the normal distribution's for dof beyond 1e6).
double twoSidedP(double t, double dof);

} // namespace lray::compare
