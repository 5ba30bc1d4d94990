// Pipeline: render. See sample_buffer.h.
#include "render/sample_buffer.h"

#include "render/pixel_error.h"

#include <algorithm>

namespace lray {

SampleBuffer::SampleBuffer(int width, int height, int x0, int y0, int x1, int y1)
    : width_(width), height_(height), sums_(static_cast<size_t>(width) * height * 6, 0.f),
      count_(static_cast<size_t>(width) * height, 0),
      active_(static_cast<size_t>(width) * height, 1),
      inRegion_(static_cast<size_t>(width) * height, 1) {
  if (x1 <= x0 || y1 <= y0) return;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (x < x0 || x >= x1 || y < y0 || y >= y1) active_[index(x, y)] = inRegion_[index(x, y)] = 0;
}

bool SampleBuffer::anyActive(int x0, int y0, int x1, int y1) const {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      if (active_[index(x, y)]) return true;
  return false;
}

double SampleBuffer::error(size_t i) const {
  const float *s = &sums_[i * 6];
  return pixelError({s[0], s[1], s[2]}, {s[3], s[4], s[5]}, count_[i]);
}

size_t SampleBuffer::updateActive(double threshold, uint32_t maxSamples) {
  // Not converged, then dilated by one pixel so the neighbours of a noisy
  // pixel (the other side of an edge, say) are not starved.
  std::vector<uint8_t> noisy(active_.size(), 0);
  for (size_t i = 0; i < noisy.size(); ++i)
    noisy[i] = inRegion_[i] && count_[i] < maxSamples && (threshold <= 0 || error(i) >= threshold);
  size_t active = 0;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      bool on = false;
      for (int dy = -1; dy <= 1 && !on; ++dy) {
        const int ny = y + dy;
        if (ny < 0 || ny >= height_) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx;
          if (nx >= 0 && nx < width_ && noisy[index(nx, ny)]) {
            on = true;
            break;
          }
        }
      }
      active_[i] = on && inRegion_[i] && count_[i] < maxSamples;
      active += active_[i];
    }
  }
  return active;
}

void SampleBuffer::writeTo(Film &film) const {
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      const float *s = &sums_[i * 6];
      const uint32_t n = count_[i];
      film.set(x, y, n ? Color(s[0], s[1], s[2]) / static_cast<double>(n) : Color());
      film.setError(x, y, static_cast<float>(error(i)));
      film.setSampleCount(x, y, n);
    }
  }
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
