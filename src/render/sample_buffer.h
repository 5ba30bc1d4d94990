// Pipeline: render. What adaptive sampling keeps per pixel between passes:
// the sums of all samples and of the odd-numbered ones (for the error
// estimate), the sample count, and whether the pixel takes part in the
// next pass.
#pragma once

#include "math/color.h"
#include "render/film.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lray {

class SampleBuffer {
public:
  /// Pixels outside `region` (x0, y0, x1, y1; all of the frame when empty)
  /// never take part: inactive from the start, and never noisy neighbours.
  SampleBuffer(int width, int height, int x0 = 0, int y0 = 0, int x1 = 0, int y1 = 0);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }

  /// Adds one pass's samples of pixel i: their sum, the sum of the
  /// odd-numbered ones, and how many (summed in double by the caller, so
  /// the float sums here take one rounding per pass, not per sample).
  void add(size_t i, const Color &sum, const Color &oddSum, uint32_t samples) {
    float *s = &sums_[i * 6];
    s[0] += static_cast<float>(sum.r);
    s[1] += static_cast<float>(sum.g);
    s[2] += static_cast<float>(sum.b);
    s[3] += static_cast<float>(oddSum.r);
    s[4] += static_cast<float>(oddSum.g);
    s[5] += static_cast<float>(oddSum.b);
    count_[i] += samples;
  }
  uint32_t count(size_t i) const { return count_[i]; }
  bool active(size_t i) const { return active_[i] != 0; }
  /// Whether any pixel of the rectangle [x0,x1) x [y0,y1) is active.
  bool anyActive(int x0, int y0, int x1, int y1) const;

  double error(size_t i) const;

  /// After a pass that brought every active pixel to `target` samples:
  /// a pixel stays active for the next pass if it or one of its eight
  /// neighbours has not converged (error >= threshold; never with
  /// threshold 0), unless it already has `maxSamples`. Returns how many
  /// pixels are active.
  size_t updateActive(double threshold, uint32_t maxSamples);

  /// The averaged colours, estimates and counts, and the report's figures.
  void writeTo(Film &film) const;

private:
  int width_, height_;
  std::vector<float> sums_; ///< per pixel: sum r,g,b, odd sum r,g,b
  std::vector<uint32_t> count_;
  std::vector<uint8_t> active_;
  std::vector<uint32_t> activeList_; ///< the indices of the active pixels
  std::vector<uint8_t> inRegion_;
};

/// The report's sample and error figures (samples, maxPixelSamples,
/// hasError, meanError and maxError over the pixels with two or more
/// samples) from the film's own error and sample-count channels.
void summarizeSampling(Film &film);

} // namespace lray
