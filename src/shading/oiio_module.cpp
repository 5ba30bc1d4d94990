// Pipeline: shading (a module of its own). Everything of LRay that uses
// OpenImageIO: decoding texture images and writing float (EXR) images.
// Built as liblray_oiio.so and loaded by oiio_library.cpp on first use, so
// the renderer does not load OpenImageIO's 260 libraries when a scene has
// no image texture and the output is PNG or TGA.
#include "shading/oiio_library.h"

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {
namespace {

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Packs `nch` channels per texel into RGB: grey (and grey + alpha) is
/// replicated, alpha and further channels dropped.
template <class T, class Convert>
void toRgb(const std::vector<T> &src, int nch, size_t texels, std::vector<float> &rgb,
           Convert convert) {
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

TextureImage readImage(const std::string &path, bool linearWorkflow, const SourceLocation &loc) {
  // Colours as stored: OIIO would otherwise premultiply PNG/TGA colours by
  // their alpha, darkening textures whose alpha is not 255.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    std::string why = OIIO::geterror();
    throw SceneError(loc, "ImagePigment2D: cannot read image '" + path + "'" +
                              (why.empty() ? std::string() : " (" + why + ")"));
  }
  const OIIO::ImageSpec &spec = in->spec();
  int nch = spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || nch <= 0) {
    throw SceneError(loc, "ImagePigment2D: image '" + path + "' is empty");
  }
  size_t texels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  // The header's size is checked before anything is allocated from it: a
  // 100000 x 100000 header in a tiny file would ask for 120 GB.
  if (texels > kMaxTextureTexels)
    throw SceneError(loc, "ImagePigment2D: image '" + path + "' is " + std::to_string(spec.width) +
                              " x " + std::to_string(spec.height) + " texels, more than the " +
                              "limit of " + std::to_string(kMaxTextureTexels));
  TextureImage image;
  image.width = spec.width;
  image.height = spec.height;
  bool ok = false;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    std::vector<uint8_t> data(texels * nch);
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, data.data());
    std::array<float, 256> lut{};
    for (int i = 0; i < 256; ++i) {
      float c = static_cast<float>(i) / 255.0f;
      lut[i] = linearWorkflow ? srgbToLinear(c) : c;
    }
    if (ok) toRgb(data, nch, texels, image.rgb, [&](uint8_t v) { return lut[v]; });
  } else {
    std::vector<float> data(texels * nch);
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, data.data());
    // A NaN or Inf texel would poison every pixel that filters it.
    auto finite = [](float v) { return std::isfinite(v) ? v : 0.0f; };
    if (ok) toRgb(data, nch, texels, image.rgb, finite);
  }
  if (!ok) {
    std::string why = in->geterror();
    throw SceneError(loc, "ImagePigment2D: cannot decode image '" + path + "'" +
                              (why.empty() ? std::string() : " (" + why + ")"));
  }
  in->close();
  return image;
}

std::string writeFloat(const std::string &path, int width, int height,
                       const std::vector<std::string> &channels, const float *pixels) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return OIIO::geterror();
  OIIO::ImageSpec spec(width, height, static_cast<int>(channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channels;
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels) || !out->close())
    return out->geterror();
  return {};
}

} // namespace

} // namespace lray

extern "C" const lray::OiioLibrary *lray_oiio_library() {
  static const lray::OiioLibrary library{&lray::readImage, &lray::writeFloat};
  return &library;
}
