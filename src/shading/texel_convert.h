// Pipeline: shading. How decoded texels become a TextureImage's linear RGB
// floats, shared by the two decoders (texture_file.cpp for PNG and TGA,
// oiio_module.cpp for everything else) so both give the same values.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lray {

inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Packs `nch` channels per texel into RGB: grey (and grey + alpha) is
/// replicated, alpha and further channels dropped.
template <class T, class Convert>
void toRgb(const T *src, int nch, size_t texels, std::vector<float> &rgb, Convert convert) {
  rgb.resize(3 * texels);
  for (size_t k = 0; k < texels; ++k) {
    const T *px = &src[k * nch];
    if (nch >= 3) {
      rgb[3 * k] = convert(px[0]);
      rgb[3 * k + 1] = convert(px[1]);
      rgb[3 * k + 2] = convert(px[2]);
    } else {
      float g = convert(px[0]);
      rgb[3 * k] = rgb[3 * k + 1] = rgb[3 * k + 2] = g;
    }
  }
}

/// The float of each 8-bit value: v / 255, decoded from sRGB under the
/// linear workflow.
inline std::array<float, 256> eightBitTable(bool linearWorkflow) {
  std::array<float, 256> lut{};
  for (int i = 0; i < 256; ++i) {
    float c = static_cast<float>(i) / 255.0f;
    lut[i] = linearWorkflow ? srgbToLinear(c) : c;
  }
  return lut;
}

} // namespace lray
