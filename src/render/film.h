// Pipeline: render. The frame buffer: one averaged, unclamped RGB value per
// pixel, filled tile by tile; quantised only when an LDR file is written.
#pragma once

#include "math/color.h"

#include <cstddef>
#include <vector>

namespace lray {

/// Row-major RGB float image; row 0 is the top of the picture.
class Film {
public:
  Film(int width, int height)
      : width_(width), height_(height), rgb_(static_cast<size_t>(width) * height * 3, 0.f) {}

  int width() const { return width_; }
  int height() const { return height_; }
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
  const std::vector<float> &data() const { return rgb_; }

private:
  int width_, height_;
  std::vector<float> rgb_;
};

} // namespace lray
