// Pipeline: render. What adaptive sampling keeps per pixel between passes:
// the sum of its samples, of their squares (for the variance of its mean,
// which its error estimate rests on: render/pixel_error.h), the sample
// count, and whether the pixel takes part in the next pass.
#pragma once

#include "math/color.h"
#include "render/film.h"
#include "render/frame_settings.h"
#include "render/pixel_error.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lray {

/// How much an edge between two centre samples shows, seen from the one of
/// colour `c`: the standard error of the mean of the two (half their
/// difference, relative to the square root of their mean brightness),
/// without its factor sqrt(2 / pi): one centre is a single sample, so an
/// edge between two is looked for a little harder. Not symmetric in the
/// last bits (the brightness is summed from c's channels on).
inline double centrePairContrast(const Color &c, const Color &d) {
  const double difference = std::abs(c.r - d.r) + std::abs(c.g - d.g) + std::abs(c.b - d.b);
  if (difference == 0) return 0; // most of a frame: no edge, and no square root
  const double brightness = std::max(0.0, (c.r + c.g + c.b + d.r + d.g + d.b) / 2);
  return 0.5 * difference / (1e-4 + std::sqrt(brightness));
}

class SampleBuffer {
public:
  /// Pixels outside `region` (x0, y0, x1, y1; all of the frame when empty)
  /// never take part: inactive from the start, and never noisy neighbours.
  /// `samples`: what the pixels' samples are, for their error estimates.
  SampleBuffer(int width, int height, SampleSet samples = SampleSet::Independent, int x0 = 0,
               int y0 = 0, int x1 = 0, int y1 = 0);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }

  /// Adds one pass's samples of pixel i: their sum, the sum of their
  /// squares, and how many (summed in double by the caller, so the float
  /// sums here take one rounding per pass, not per sample). The squares are
  /// kept about the pixel's first mean (`shift`), so that the variance does
  /// not cancel away in float.
  void add(size_t i, const Color &sum, const Color &squares, uint32_t samples) {
    float *q = &squares_[i * kSquareFloats];
    if (count_[i] == 0 && samples > 0) {
      const Color first = sum / static_cast<double>(samples);
      q[3] = static_cast<float>(first.r);
      q[4] = static_cast<float>(first.g);
      q[5] = static_cast<float>(first.b);
    }
    // sum (x - m)^2 = sum x^2 - 2 m sum x + k m^2, in double over one pass.
    const double k = samples;
    q[0] += static_cast<float>(squares.r - 2 * q[3] * sum.r + k * q[3] * q[3]);
    q[1] += static_cast<float>(squares.g - 2 * q[4] * sum.g + k * q[4] * q[4]);
    q[2] += static_cast<float>(squares.b - 2 * q[5] * sum.b + k * q[5] * q[5]);
    float *s = &sums_[i * 3];
    s[0] += static_cast<float>(sum.r);
    s[1] += static_cast<float>(sum.g);
    s[2] += static_cast<float>(sum.b);
    count_[i] += samples;
  }
  /// The centre-first pass: pixel i's one sample, through its centre (the
  /// pixel has no samples yet), or filled from its neighbours' (`traced`
  /// false: --sparse-centres). Its squares stay the 0 they start as, so
  /// the pages of a frame that stops at its centres are never written.
  void setCentre(size_t i, const Color &c, bool traced = true) {
    assert(count_[i] == 0);
    float *s = &sums_[i * 3];
    s[0] = static_cast<float>(c.r);
    s[1] = static_cast<float>(c.g);
    s[2] = static_cast<float>(c.b);
    count_[i] = 1;
    centreOnly_[i] = traced ? kTracedCentre : kFilledCentre;
  }
  /// Whether pixel i's one sample is a centre --sparse-centres filled.
  bool filled(size_t i) const { return centreOnly_[i] == kFilledCentre; }
  /// A pixel that has only its centre sample drops it before its Sobol
  /// samples (which then form the pixel's whole, stratified set): returns
  /// whether it did.
  bool restart(size_t i) {
    if (!centreOnly_[i]) return false;
    std::fill_n(&sums_[i * 3], 3, 0.f);
    std::fill_n(&squares_[i * kSquareFloats], kSquareFloats, 0.f);
    count_[i] = 0;
    centreOnly_[i] = 0;
    return true;
  }
  /// A pixel refined on its edge lattice (render/pixel_lattice.h): its
  /// colour and the lattice points it rests on replace its centre sample,
  /// and it stops. Its estimate is 0 (no spread: the points are not random
  /// samples).
  void setRefined(size_t i, const Color &c, uint32_t points) {
    active_[i] = 0;
    float *s = &sums_[i * 3];
    s[0] = static_cast<float>(c.r * points);
    s[1] = static_cast<float>(c.g * points);
    s[2] = static_cast<float>(c.b * points);
    count_[i] = points;
    centreOnly_[i] = 0;
    refined_[i] = 1;
  }
  /// Pixel i's mean colour (it has samples; a centre-only pixel's, its
  /// one sample).
  Color mean(size_t i) const;
  uint32_t count(size_t i) const { return count_[i]; }
  bool active(size_t i) const {
    return active(static_cast<int>(i % static_cast<size_t>(width_)),
                  static_cast<int>(i / static_cast<size_t>(width_)));
  }
  bool active(int x, int y) const {
    return wholeRegionActive_ ? inRegion(x, y) : active_[index(x, y)] != 0;
  }
  /// Whether any pixel of the rectangle [x0,x1) x [y0,y1) is active.
  bool anyActive(int x0, int y0, int x1, int y1) const;

  /// Pixel i's error estimate (render/pixel_error.h; 0 below two samples).
  double error(size_t i) const;
  /// For a pixel with only its centre sample: the largest standard error
  /// its mean would have were its two samples its own and one of its eight
  /// neighbours' (centrePairContrast), i.e. how much an edge between them
  /// shows. The definition updateActive's verdicts after the centre-first
  /// pass follow (they take each pair of neighbours once, for both).
  double centreContrast(size_t i) const;

  /// After a pass that brought every active pixel to `target` samples:
  /// a pixel stays active for the next pass if it or one of its eight
  /// neighbours has not converged (error >= threshold; never with
  /// threshold 0), unless it already has `maxSamples`. After the
  /// centre-first pass: if its centreContrast is threshold or more, or
  /// that of most of its neighbours (setActiveAround). Only active pixels
  /// are judged: an inactive one was not noisy when it stopped and has not
  /// changed since (a centre-only pixel is judged once, after the centre
  /// pass, not again as its neighbours refine; the crop margin counts on
  /// that).
  /// Returns how many pixels are active.
  size_t updateActive(double threshold, uint32_t maxSamples);

  /// The averaged colours, estimates and counts, and the report's figures.
  void writeTo(Film &film) const;
  /// writeTo, the last use of the buffer: the film (new, as for
  /// Film::setSamples) takes its sums, averaged where they lie, and its
  /// counts, instead of copies of them.
  void moveTo(Film &film) &&;

  /// Per pixel, whether centreContrast(i) >= threshold (0 for a pixel
  /// without samples), the pairs of neighbours taken once (updateActive's
  /// first verdicts after the centre-first pass; public for tests).
  std::vector<uint8_t> centreEdges(double threshold) const;

private:
  /// The variance of pixel i's mean, per channel (0 below two samples).
  Color variance(size_t i) const;
  /// Pixel i's verdict: not converged (below maxSamples, and an error of
  /// threshold or more, or `edge` for a pixel of only its centre).
  bool isNoisy(size_t i, double threshold, uint32_t maxSamples, bool edge) const;
  /// updateActive's first verdicts, on every pixel of the region.
  size_t judgeRegion(double threshold, uint32_t maxSamples);
  /// Sets each pixel of the region active (below maxSamples) where it is
  /// `noisy` (per pixel of the frame, 0 or 1) or where its neighbours are:
  /// after the centre-first pass (`centres`) most of them, else any one.
  void setActiveAround(const std::vector<uint8_t> &noisy, bool centres, uint32_t maxSamples);
  bool inRegion(int x, int y) const {
    return x >= region_.x0 && x < region_.x1 && y >= region_.y0 && y < region_.y1;
  }

  int width_, height_;
  SampleSet samples_;
  PixelWindow region_; ///< the pixels that take part
  // Zeroed by calloc (util/zeroed_vector.h): the render threads map them.
  ZeroedVector<float> sums_; ///< per pixel: sum r,g,b
  /// Floats of squares_ a pixel: the sums of (sample - shift)^2 in r,g,b,
  /// then the shift (moveTo writes the pixel's estimate in their place).
  static constexpr size_t kSquareFloats = 6;
  /// per pixel: the sums of (sample - shift)^2 in r,g,b, then the shift
  ZeroedVector<float> squares_;
  ZeroedVector<uint32_t> count_;
  /// Whether each pixel is active (once wholeRegionActive_ is false).
  ZeroedVector<uint8_t> active_;
  /// Until the first verdicts: every pixel of the region is active, and
  /// neither active_ nor activeList_ says so.
  bool wholeRegionActive_ = true;
  std::vector<uint32_t> activeList_; ///< the indices of the active pixels
  /// The pixel's one sample is its centre (traced or filled), else 0.
  ZeroedVector<uint8_t> centreOnly_;
  static constexpr uint8_t kTracedCentre = 1, kFilledCentre = 2;
  /// The pixel was refined on its edge lattice: its squares were never
  /// written (its estimate is their 0).
  ZeroedVector<uint8_t> refined_;
};

/// The report's sample and error figures (samples, maxPixelSamples,
/// hasError, meanError and maxError over the pixels with two or more
/// samples) from the film's own error and sample-count channels.
void summarizeSampling(Film &film);

} // namespace lray
