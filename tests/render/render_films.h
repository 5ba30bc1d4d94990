// Test helpers for the render tests: a frame rendered into a Film, and the
// RMSE between two films.
#pragma once

#include "render/renderer.h"
#include "shading/image_cache.h"

#include <tbb/global_control.h>

#include <cmath>

namespace lray::test {

/// Renders `fs` of `scene`; the frame's ray counts go to `counts` if given.
inline Film render(const Scene &scene, const Accelerator &accel, const FrameSettings &fs,
                   RayCounts *counts = nullptr) {
  ImageCache images(false);
  RayCounts c;
  Film film = renderFrame(scene, accel, images, fs, c);
  if (counts) *counts = c;
  return film;
}

/// render with at most `threads` threads (for a frame that must come out the
/// same bytes for any thread count).
inline Film renderOnThreads(const Scene &scene, const Accelerator &accel, const FrameSettings &fs,
                            int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<size_t>(threads));
  return render(scene, accel, fs);
}

/// Adaptive sampling from the centre-first pass (--min-samples 1) to
/// `threshold`, at most `maxSamples` a pixel, light cells spread.
inline FrameSettings centreFirstSettings(int width, int height, double threshold,
                                         int maxSamples) {
  FrameSettings fs;
  fs.width = width;
  fs.height = height;
  fs.adaptive = true;
  fs.lightSampling = LightSampling::Spread;
  fs.adaptiveSettings.noiseThreshold = threshold;
  fs.adaptiveSettings.minSamples = 1;
  fs.adaptiveSettings.maxSamples = maxSamples;
  return fs;
}

/// The RMSE between two films' colours, over every channel of every pixel.
inline double rmse(const Film &a, const Film &b) {
  double sum = 0;
  for (size_t i = 0; i < a.data().size(); ++i) {
    const double d = a.data()[i] - b.data()[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(a.data().size()));
}

} // namespace lray::test
