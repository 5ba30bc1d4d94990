// Test helpers for the render tests: a frame rendered into a Film, and the
// RMSE between two films.
#pragma once

#include "render/renderer.h"
#include "shading/image_cache.h"

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
