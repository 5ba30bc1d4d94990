// Pipeline: render. The frame buffer: one averaged, unclamped RGB value per
// pixel, filled tile by tile; quantised only when an LDR file is written.
// Beside the colour it keeps each pixel's error estimate, the variance of
// its mean and its sample count, and how the frame's sampling ended.
#pragma once

#include "math/color.h"
#include "render/pixel_error.h"
#include "util/zeroed_vector.h"

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace lray {

/// How the samples of a frame went (render/pixel_error.h for the estimate).
struct SamplingReport {
  uint64_t samples = 0;     ///< camera samples taken, all pixels together
  uint32_t maxPixelSamples = 0;
  int passes = 0;           ///< 1 for fixed sampling
  bool timeLimitHit = false;///< the render stopped at --time-limit
  bool cancelled = false;   ///< stopped by FrameSettings::cancel
  double meanError = 0;     ///< over pixels with an estimate (>= 2 samples)
  double maxError = 0;
  bool hasError = false;    ///< false when every pixel took one sample
};

/// Row-major RGB float image; row 0 is the top of the picture.
class Film {
public:
  Film(int width, int height)
      : width_(width), height_(height), rgb_(pixels() * 3),
        estimates_(pixels() * kEstimateFloats), samples_(pixels()) {}

  /// Floats a pixel's estimate takes (estimateData()): the variance of its
  /// mean (r, g, b), then its error estimate.
  static constexpr size_t kEstimateFloats = 4;
  /// Where in a pixel's estimate its error estimate lies.
  static constexpr size_t kErrorFloat = 3;
  /// Writes the estimate setEstimate gives into a pixel's slot `e`.
  static void writeEstimate(float *e, const Color &mean, const Color &variance, uint32_t count,
                            SampleSet samples) {
    e[0] = static_cast<float>(variance.r);
    e[1] = static_cast<float>(variance.g);
    e[2] = static_cast<float>(variance.b);
    e[kErrorFloat] = static_cast<float>(pixelError(mean, variance, count, samples));
  }

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixels() const { return static_cast<size_t>(width_) * height_; }
  void set(int x, int y, const Color &c) {
    float *p = &rgb_[(static_cast<size_t>(y) * width_ + x) * 3];
    p[0] = static_cast<float>(c.r);
    p[1] = static_cast<float>(c.g);
    p[2] = static_cast<float>(c.b);
  }
  Color get(int x, int y) const {
    const float *p = &rgb_[(static_cast<size_t>(y) * width_ + x) * 3];
    return {p[0], p[1], p[2]};
  }
  const ZeroedVector<float> &data() const { return rgb_; }
  /// A rendered pixel: the mean of its `count` samples, the variance of
  /// that mean as independent samples would give it (EXR's Variance:
  /// lray-compare's noise test rests on it), and the error estimate made of
  /// the two for samples of the kind `samples` (pixelError: 0 below two
  /// samples, whose variance is 0). Once per pixel of a new film: below two
  /// samples the error and variance stay the 0 the film starts with, so a
  /// frame of one-sample pixels never writes (maps) their pages.
  void setSamples(int x, int y, const Color &mean, const Color &variance, uint32_t count,
                  SampleSet samples) {
    set(x, y, mean);
    setSampleCount(x, y, count);
    if (count >= 2) setEstimate(x, y, mean, variance, count, samples);
  }
  /// The error estimate and variance setSamples writes for a pixel of two
  /// samples or more.
  void setEstimate(int x, int y, const Color &mean, const Color &variance, uint32_t count,
                   SampleSet samples) {
    writeEstimate(estimate(x, y), mean, variance, count, samples);
  }

  /// Takes `rgb` (three floats a pixel, as data()), `samples` (a count a
  /// pixel) and `estimates` (`stride` floats a pixel, each pixel's first
  /// kEstimateFloats as estimateData()'s, 0 below two samples) as its
  /// colours, sample counts and estimates (SampleBuffer::moveTo: the
  /// estimates in place of its squares, so the film writes no page the
  /// render left unmapped).
  void adopt(ZeroedVector<float> &&rgb, ZeroedVector<uint32_t> &&samples,
             ZeroedVector<float> &&estimates, size_t stride) {
    assert(rgb.size() == rgb_.size() && samples.size() == samples_.size() &&
           stride >= kEstimateFloats && estimates.size() == pixels() * stride);
    rgb_ = std::move(rgb);
    samples_ = std::move(samples);
    estimates_ = std::move(estimates);
    estimateStride_ = stride;
  }

  /// The pixel's error estimate (0 with fewer than two samples).
  float error(int x, int y) const { return estimate(x, y)[kErrorFloat]; }
  void setError(int x, int y, float e) { estimate(x, y)[kErrorFloat] = e; }
  uint32_t sampleCount(int x, int y) const { return samples_[static_cast<size_t>(y) * width_ + x]; }
  void setSampleCount(int x, int y, uint32_t n) {
    samples_[static_cast<size_t>(y) * width_ + x] = n;
  }
  /// Every pixel's estimate: kEstimateFloats a pixel, or the stride a film
  /// adopted them with (the floats past kEstimateFloats then 0).
  const ZeroedVector<float> &estimateData() const { return estimates_; }
  /// The variance of the pixel's value (the mean of its samples) per
  /// channel: the samples' variance over their count (0 below two samples).
  /// lray-compare's noise-aware test reads it from the EXR (Variance.R/G/B).
  Color variance(int x, int y) const {
    const float *v = estimate(x, y);
    return {v[0], v[1], v[2]};
  }
  void setVariance(int x, int y, const Color &v) {
    float *p = estimate(x, y);
    p[0] = static_cast<float>(v.r);
    p[1] = static_cast<float>(v.g);
    p[2] = static_cast<float>(v.b);
  }

  /// The layers for denoisers and compositors, per pixel, averaged over a
  /// 4 x 4 grid of camera rays (render/tile_renderer_impl.h): camera-space
  /// depth Z of the first hit (+inf where every ray missed), the
  /// camera-space unit shading normal facing the camera, and the albedo
  /// (pigment colour), both 0 where rays miss. Empty unless enabled.
  struct Aov {
    float z;
    float n[3];
    float albedo[3];
  };
  void enableAovs() { aov_.assign(pixels(), Aov{}); }
  bool hasAovs() const { return !aov_.empty(); }
  Aov &aov(int x, int y) { return aov_[static_cast<size_t>(y) * width_ + x]; }
  const Aov &aov(int x, int y) const { return aov_[static_cast<size_t>(y) * width_ + x]; }

  SamplingReport report;

  /// The memory its pixels hold.
  size_t memoryBytes() const {
    return (rgb_.size() + estimates_.size()) * sizeof(float) +
           samples_.size() * sizeof(uint32_t) + aov_.size() * sizeof(Aov);
  }

private:
  float *estimate(int x, int y) {
    return &estimates_[(static_cast<size_t>(y) * width_ + x) * estimateStride_];
  }
  const float *estimate(int x, int y) const {
    return &estimates_[(static_cast<size_t>(y) * width_ + x) * estimateStride_];
  }

  int width_, height_;
  // Zeroed by calloc (util/zeroed_vector.h): the render threads map them.
  ZeroedVector<float> rgb_;
  ZeroedVector<float> estimates_;
  size_t estimateStride_ = kEstimateFloats;
  ZeroedVector<uint32_t> samples_;
  std::vector<Aov> aov_;
};

} // namespace lray
