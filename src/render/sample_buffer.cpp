// Pipeline: render. See sample_buffer.h.
#include "render/sample_buffer.h"

#include "render/flush_to_zero.h"
#include "render/pixel_error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace lray {

SampleBuffer::SampleBuffer(int width, int height, SampleSet samples, int x0, int y0, int x1,
                           int y1)
    : width_(width), height_(height), samples_(samples),
      sums_(static_cast<size_t>(width) * height * 3),
      squares_(static_cast<size_t>(width) * height * 6),
      count_(static_cast<size_t>(width) * height),
      active_(static_cast<size_t>(width) * height, 1),
      inRegion_(static_cast<size_t>(width) * height, 1),
      centreOnly_(static_cast<size_t>(width) * height) {
  if (x1 > x0 && y1 > y0)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        if (x < x0 || x >= x1 || y < y0 || y >= y1)
          active_[index(x, y)] = inRegion_[index(x, y)] = 0;
  activeList_.reserve(active_.size());
  for (size_t i = 0; i < active_.size(); ++i)
    if (active_[i]) activeList_.push_back(static_cast<uint32_t>(i));
}

bool SampleBuffer::anyActive(int x0, int y0, int x1, int y1) const {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      if (active_[index(x, y)]) return true;
  return false;
}

double SampleBuffer::error(size_t i) const {
  if (count_[i] < 2) return 0;
  return pixelError(mean(i), variance(i), count_[i], samples_);
}

Color SampleBuffer::variance(size_t i) const {
  const float *s = &sums_[i * 3];
  const float *q = &squares_[i * 6];
  const uint32_t n = count_[i];
  const Color shifted = Color(s[0], s[1], s[2]) - Color(q[3], q[4], q[5]) * n;
  return varianceOfMean(shifted, {q[0], q[1], q[2]}, n);
}

Color SampleBuffer::mean(size_t i) const {
  const float *s = &sums_[i * 3];
  // One sample (a centre) is its own mean: no division, the same value.
  if (count_[i] == 1) return {s[0], s[1], s[2]};
  const double n = count_[i];
  return {s[0] / n, s[1] / n, s[2] / n};
}

double SampleBuffer::centreContrast(size_t i, double enough) const {
  const int x = static_cast<int>(i % static_cast<size_t>(width_));
  const int y = static_cast<int>(i / static_cast<size_t>(width_));
  const Color c = mean(i);
  double most = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
      const size_t j = index(nx, ny);
      if (j == i || !count_[j]) continue;
      const Color d = mean(j);
      const double difference = std::abs(c.r - d.r) + std::abs(c.g - d.g) + std::abs(c.b - d.b);
      if (difference == 0) continue; // most of a frame: no edge, and no square root
      const double brightness = std::max(0.0, (c.r + c.g + c.b + d.r + d.g + d.b) / 2);
      most = std::max(most, 0.5 * difference / (1e-4 + std::sqrt(brightness)));
      if (most >= enough) return most;
    }
  return most;
}

size_t SampleBuffer::updateActive(double threshold, uint32_t maxSamples) {
  // Not converged, then dilated by one pixel so the neighbours of a noisy
  // pixel (the other side of an edge, say) are not starved. Only active
  // pixels can be noisy: an inactive one had no noisy pixel around it, so
  // was not noisy itself, and took no samples since. So the work is in
  // proportion to the active pixels, not the frame. A verdict reads only
  // the pixel's and its neighbours' sums, so they are reached in parallel
  // (after the centre-first pass, one per pixel of the frame).
  auto isNoisy = [&](uint32_t i) {
    if (count_[i] >= maxSamples) return false;
    if (threshold <= 0) return true;
    return (centreOnly_[i] ? centreContrast(i, threshold) : error(i)) >= threshold;
  };
  std::vector<uint8_t> verdicts(activeList_.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, activeList_.size(), 4096),
                    [&](const tbb::blocked_range<size_t> &r) {
                      setFlushToZero();
                      for (size_t k = r.begin(); k != r.end(); ++k)
                        verdicts[k] = isNoisy(activeList_[k]);
                    });
  std::vector<uint32_t> noisy;
  for (size_t k = 0; k < activeList_.size(); ++k) {
    active_[activeList_[k]] = 0;
    if (verdicts[k]) noisy.push_back(activeList_[k]);
  }
  activeList_.clear();
  for (uint32_t i : noisy) {
    const int x = static_cast<int>(i % static_cast<uint32_t>(width_));
    const int y = static_cast<int>(i / static_cast<uint32_t>(width_));
    for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny)
      for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
        const size_t j = index(nx, ny);
        if (active_[j] || !inRegion_[j] || count_[j] >= maxSamples) continue;
        active_[j] = 1;
        activeList_.push_back(static_cast<uint32_t>(j));
      }
  }
  return activeList_.size();
}

void SampleBuffer::writeTo(Film &film) const {
  // By rows in parallel: the film's pages are mapped as they are written.
  tbb::parallel_for(0, height_, [&](int y) {
    setFlushToZero();
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      const uint32_t n = count_[i];
      film.setSamples(x, y, n ? mean(i) : Color(), variance(i), n, samples_);
    }
  });
  summarizeSampling(film);
}

void summarizeSampling(Film &film) {
  double errorSum = 0, errorMax = 0;
  size_t withError = 0;
  uint64_t samples = 0;
  uint32_t most = 0;
  for (int y = 0; y < film.height(); ++y) {
    for (int x = 0; x < film.width(); ++x) {
      const uint32_t n = film.sampleCount(x, y);
      samples += n;
      most = std::max(most, n);
      if (n >= 2) {
        const double e = film.error(x, y);
        errorSum += e;
        errorMax = std::max(errorMax, e);
        ++withError;
      }
    }
  }
  SamplingReport &r = film.report;
  r.samples = samples;
  r.maxPixelSamples = most;
  r.hasError = withError > 0;
  r.meanError = withError ? errorSum / static_cast<double>(withError) : 0;
  r.maxError = errorMax;
}

} // namespace lray
