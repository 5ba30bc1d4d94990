#include "compare/ssim.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace lray::compare {

namespace {

constexpr int kRadius = 5; // 11 taps
constexpr double kSigma = 1.5;

std::array<double, 2 * kRadius + 1> gaussian() {
  std::array<double, 2 * kRadius + 1> w{};
  double sum = 0;
  for (int i = -kRadius; i <= kRadius; ++i)
    sum += w[i + kRadius] = std::exp(-i * i / (2 * kSigma * kSigma));
  for (double &v : w)
    v /= sum;
  return w;
}

/// The separable Gaussian filter of `in` at the "valid" positions: out is
/// (width - 2r) x (height - 2r), r the window radius cut to the image.
std::vector<double> filterValid(const std::vector<double> &in, int width, int height, int r) {
  const auto full = gaussian();
  std::vector<double> w(full.begin() + (kRadius - r), full.end() - (kRadius - r));
  double sum = 0;
  for (double v : w)
    sum += v;
  for (double &v : w)
    v /= sum;
  const int ow = width - 2 * r, oh = height - 2 * r;
  std::vector<double> rows(static_cast<size_t>(ow) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int k = 0; k <= 2 * r; ++k)
        s += w[k] * in[static_cast<size_t>(y) * width + x + k];
      rows[static_cast<size_t>(y) * ow + x] = s;
    }
  std::vector<double> out(static_cast<size_t>(ow) * oh);
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0;
      for (int k = 0; k <= 2 * r; ++k)
        s += w[k] * rows[static_cast<size_t>(y + k) * ow + x];
      out[static_cast<size_t>(y) * ow + x] = s;
    }
  return out;
}

} // namespace

SsimResult ssimChannel(const std::vector<float> &a, const std::vector<float> &b, int width,
                       int height) {
  const int r = std::min(kRadius, (std::min(width, height) - 1) / 2);
  const size_t n = static_cast<size_t>(width) * height;
  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = std::clamp<double>(a[i], 0, 1);
    y[i] = std::clamp<double>(b[i], 0, 1);
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  const auto mx = filterValid(x, width, height, r), my = filterValid(y, width, height, r),
             mxx = filterValid(xx, width, height, r), myy = filterValid(yy, width, height, r),
             mxy = filterValid(xy, width, height, r);
  constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  SsimResult result;
  result.map.assign(n, 1.f);
  const int ow = width - 2 * r, oh = height - 2 * r;
  double total = 0;
  for (int j = 0; j < oh; ++j)
    for (int i = 0; i < ow; ++i) {
      const size_t k = static_cast<size_t>(j) * ow + i;
      const double vx = mxx[k] - mx[k] * mx[k], vy = myy[k] - my[k] * my[k],
                   cxy = mxy[k] - mx[k] * my[k];
      const double s = (2 * mx[k] * my[k] + c1) * (2 * cxy + c2) /
                       ((mx[k] * mx[k] + my[k] * my[k] + c1) * (vx + vy + c2));
      result.map[static_cast<size_t>(j + r) * width + i + r] = static_cast<float>(s);
      total += s;
    }
  result.mean = total / (static_cast<double>(ow) * oh);
  return result;
}

SsimResult ssim(const CompareImage &a, const CompareImage &b) {
  const size_t n = a.pixels();
  SsimResult result;
  result.mean = 0;
  result.map.assign(n, 0.f);
  std::vector<float> ca(n), cb(n);
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < n; ++i) {
      ca[i] = a.rgb[i * 3 + c];
      cb[i] = b.rgb[i * 3 + c];
    }
    const SsimResult one = ssimChannel(ca, cb, a.width, a.height);
    result.mean += one.mean / 3;
    for (size_t i = 0; i < n; ++i)
      result.map[i] += one.map[i] / 3;
  }
  return result;
}

} // namespace lray::compare
