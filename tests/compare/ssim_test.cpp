// SSIM (compare/ssim.h) against scikit-image 0.26's structural_similarity
// with Wang et al.'s settings (gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=1), which reproduces the
// authors' ssim_index.m, on images both compute from the same formulas:
//   y, x = np.mgrid[0:48, 0:64]; a = 0.5 + 0.4 sin(0.3x) cos(0.2y)
//   b = a + 0.05 sin(1.7x + 2.3y); c = 0.8a + 0.1
//   d = clip(a + 0.2 (((7x + 13y) mod 5) - 2) / 2, 0, 1)   (all float32)
#include "compare/ssim.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace lray::compare;

namespace {

constexpr int kW = 64, kH = 48;

std::vector<float> make(char which) {
  std::vector<float> out(kW * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float a = static_cast<float>(0.5 + 0.4 * std::sin(0.3 * x) * std::cos(0.2 * y));
      float v = a;
      if (which == 'b') v = static_cast<float>(a + 0.05 * std::sin(1.7 * x + 2.3 * y));
      if (which == 'c') v = static_cast<float>(0.8 * a + 0.1);
      if (which == 'd')
        v = static_cast<float>(std::clamp(a + 0.2 * (((x * 7 + y * 13) % 5) - 2) / 2, 0.0, 1.0));
      out[static_cast<size_t>(y) * kW + x] = v;
    }
  return out;
}

} // namespace

TEST(Ssim, MatchesScikitImageWithWangsSettings) {
  const auto a = make('a');
  EXPECT_NEAR(ssimChannel(a, make('b'), kW, kH).mean, 0.9296322773410511, 2e-6);
  EXPECT_NEAR(ssimChannel(a, make('c'), kW, kH).mean, 0.9728302636503289, 2e-6);
  EXPECT_NEAR(ssimChannel(a, make('d'), kW, kH).mean, 0.47801448669634367, 2e-6);
}

TEST(Ssim, IsOneForAnImageAndItselfAndSymmetric) {
  const auto a = make('a'), b = make('b');
  EXPECT_DOUBLE_EQ(ssimChannel(a, a, kW, kH).mean, 1.0);
  EXPECT_NEAR(ssimChannel(a, b, kW, kH).mean, ssimChannel(b, a, kW, kH).mean, 1e-12);
}

TEST(Ssim, ColourImagesAverageTheirChannels) {
  CompareImage x, y;
  x.width = y.width = kW;
  x.height = y.height = kH;
  const auto a = make('a'), b = make('b'), c = make('c');
  for (size_t i = 0; i < a.size(); ++i) {
    x.rgb.insert(x.rgb.end(), {a[i], a[i], a[i]});
    y.rgb.insert(y.rgb.end(), {a[i], b[i], c[i]});
  }
  EXPECT_NEAR(ssim(x, y).mean, (1 + 0.9296322773410511 + 0.9728302636503289) / 3, 2e-6);
}

TEST(Ssim, ImagesSmallerThanTheWindowStillCompare) {
  std::vector<float> a(3 * 2, 0.5f), b(3 * 2, 0.5f);
  b[0] = 0.9f;
  const double s = ssimChannel(a, b, 3, 2).mean;
  EXPECT_LT(s, 1.0);
  EXPECT_GT(s, 0.0);
}
