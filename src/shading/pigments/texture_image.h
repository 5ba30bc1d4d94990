// Pipeline: shading. A decoded texture image (float RGB) and its wrapped
// bilinear lookup, as ImagePigment2D uses it (lua/README.md, "Textures, finishes and pigments").
#pragma once

#include "math/color.h"

#include <cstddef>
#include <vector>

namespace lray {

/// Float RGB texels, row-major with row 0 at the TOP of the image (as files
/// store it). Values are the ones shading uses: 8-bit as stored / 255, or
/// decoded from sRGB in the linear workflow; float formats as is.
struct TextureImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb; ///< 3 * width * height

  /// Texel at column i (from the left) and row j counted from the BOTTOM.
  Color texel(int i, int jFromBottom) const {
    size_t k = 3 * (static_cast<size_t>(height - 1 - jFromBottom) * width + i);
    return {rgb[k], rgb[k + 1], rgb[k + 2]};
  }

  /// The image at texture coordinate (s, t), repeating outside [0, 1):
  /// bilinear between texel centres at ((i + 0.5) / w, (j + 0.5) / h), with
  /// t = 0 the bottom edge. Non-finite coordinates read as 0.
  Color lookup(double s, double t) const;

  size_t memoryBytes() const { return rgb.capacity() * sizeof(float); }
};

} // namespace lray
