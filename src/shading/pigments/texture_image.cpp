// Pipeline: shading. Wrapped bilinear texture lookup.
#include "shading/pigments/texture_image.h"

#include <cmath>

namespace lray {
namespace {

/// Splits a coordinate into the two neighbouring texel indices (wrapped
/// into [0, n)) and the weight of the second one.
inline void texelPair(double s, int n, int &i0, int &i1, double &f) {
  if (!std::isfinite(s)) s = 0;
  s -= std::floor(s); // [0, 1], exactly 1 only by rounding of a tiny negative s
  double x = s * n - 0.5;
  double fl = std::floor(x);
  f = x - fl;
  i0 = static_cast<int>(fl); // in [-1, n]
  if (i0 < 0) i0 += n;
  if (i0 >= n) i0 -= n;
  i1 = i0 + 1 == n ? 0 : i0 + 1;
}

} // namespace

Color TextureImage::lookup(double s, double t) const {
  if (width <= 0 || height <= 0) return {};
  int i0, i1, j0, j1;
  double fs, ft;
  texelPair(s, width, i0, i1, fs);
  texelPair(t, height, j0, j1, ft);
  Color bottom = texel(i0, j0) * (1 - fs) + texel(i1, j0) * fs;
  Color top = texel(i0, j1) * (1 - fs) + texel(i1, j1) * fs;
  return bottom * (1 - ft) + top * ft;
}

} // namespace lray
