#include "compare/compare_image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace lray::compare {

namespace {

int channelIndex(const OIIO::ImageSpec &spec, const char *name) {
  for (int i = 0; i < spec.nchannels; ++i)
    if (spec.channelnames[static_cast<size_t>(i)] == name) return i;
  return -1;
}

} // namespace

CompareImage readCompareImage(const std::string &path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw CompareError("cannot read '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec &spec = in->spec();
  // Far beyond any image a test compares: a corrupt header must not make us
  // allocate terabytes.
  constexpr int64_t kMaxPixels = int64_t{1} << 28;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 ||
      int64_t{spec.width} * spec.height > kMaxPixels)
    throw CompareError("'" + path + "': unusable size " + std::to_string(spec.width) + " x " +
                       std::to_string(spec.height) + " x " + std::to_string(spec.nchannels));
  const int nc = spec.nchannels;
  std::vector<float> all(static_cast<size_t>(spec.width) * spec.height * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, all.data()))
    throw CompareError("cannot read '" + path + "': " + in->geterror());
  CompareImage image;
  image.width = spec.width;
  image.height = spec.height;
  if (spec.format == OIIO::TypeDesc::UINT8)
    image.quantum = 1.0 / 255;
  else if (spec.format == OIIO::TypeDesc::UINT16)
    image.quantum = 1.0 / 65535;
  const size_t n = image.pixels();
  // Grey images count as three equal channels.
  const int r = 0, g = std::min(1, nc - 1), b = std::min(2, nc - 1);
  const int vr = channelIndex(spec, "Variance.R"), vg = channelIndex(spec, "Variance.G"),
            vb = channelIndex(spec, "Variance.B"), count = channelIndex(spec, "SampleCount");
  const bool variance = vr >= 0 && vg >= 0 && vb >= 0;
  image.rgb.resize(n * 3);
  if (variance) image.variance.resize(n * 3);
  if (count >= 0) image.samples.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float *p = &all[i * static_cast<size_t>(nc)];
    image.rgb[i * 3] = p[r];
    image.rgb[i * 3 + 1] = p[g];
    image.rgb[i * 3 + 2] = p[b];
    if (variance) {
      image.variance[i * 3] = p[vr];
      image.variance[i * 3 + 1] = p[vg];
      image.variance[i * 3 + 2] = p[vb];
    }
    if (count >= 0) image.samples[i] = p[count];
  }
  return image;
}

void writePng(const std::string &path, int width, int height,
              const std::vector<unsigned char> &rgb) {
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
      !out->close())
    throw CompareError("cannot write '" + path +
                       "': " + (out ? out->geterror() : OIIO::geterror()));
}

} // namespace lray::compare
