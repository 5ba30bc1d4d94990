// lray-compare: the structural similarity index (Wang, Bovik, Sheikh and
// Simoncelli 2004, "Image Quality Assessment: From Error Visibility to
// Structural Similarity", IEEE TIP 13(4)), as the paper defines it and its
// authors' ssim_index.m computes it: local means, variances and covariance
// under an 11 x 11 Gaussian window of sigma 1.5 (normalised), constants
// C1 = (0.01 L)^2 and C2 = (0.03 L)^2 with L = 1 (values as stored, an
// 8-bit file's as value / 255; EXR values clamped to [0, 1] first), the
// map over the positions where the window lies inside the image ("valid"),
// and its mean. Colour images: the mean of the three channels' SSIM.
#pragma once

#include "compare/compare_image.h"

#include <vector>

namespace lray::compare {

struct SsimResult {
  double mean = 1;        ///< mean SSIM (1 for identical images)
  std::vector<float> map; ///< per pixel, the channels' mean (1 at the border)
};

/// SSIM of one channel (values row-major, width x height); images smaller
/// than the window are compared with the window cut to the image.
SsimResult ssimChannel(const std::vector<float> &a, const std::vector<float> &b, int width,
                       int height);

/// The mean of the three channels' SSIM, and the mean map.
SsimResult ssim(const CompareImage &a, const CompareImage &b);

} // namespace lray::compare
