// lray-compare: an image as the comparison sees it. Any file OpenImageIO
// reads (PNG, TGA, EXR, ...): its first three channels as floats (8-bit
// files as value / 255, as stored: no transfer curve is undone), and, from
// an EXR that lray wrote, each pixel's variance (Variance.R/G/B) and sample
// count (SampleCount), which the noise-aware test needs.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace lray::compare {

/// A file that cannot be read, or images that cannot be compared.
struct CompareError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CompareImage {
  int width = 0, height = 0;
  std::vector<float> rgb;      ///< 3 per pixel, row 0 at the top
  std::vector<float> variance; ///< 3 per pixel (of the pixel's value); empty if unknown
  std::vector<float> samples;  ///< 1 per pixel; empty if unknown
  double quantum = 0;          ///< the file's step: 1/255 for 8 bits, 0 for floats

  size_t pixels() const { return static_cast<size_t>(width) * height; }
  bool hasVariance() const { return !variance.empty(); }
  float at(int x, int y, int c) const { return rgb[(static_cast<size_t>(y) * width + x) * 3 + c]; }
};

/// Reads `path`; throws CompareError naming the path and the reason.
CompareImage readCompareImage(const std::string &path);

/// Writes 8-bit RGB bytes (3 per pixel) as a PNG; throws CompareError.
void writePng(const std::string &path, int width, int height,
              const std::vector<unsigned char> &rgb);

} // namespace lray::compare
