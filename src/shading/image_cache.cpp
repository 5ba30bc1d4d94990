// Pipeline: shading. Image decoding through OpenImageIO (the only file in
// the shading layer that sees OIIO types).
#include "shading/image_cache.h"

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

} // namespace

ImageCache::ImageCache(bool linearWorkflow) : linear_(linearWorkflow) {}

TextureImage ImageCache::readImage(const std::string &path, bool linearWorkflow,
                                   const SourceLocation &loc) {
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
  TextureImage image;
  image.width = spec.width;
  image.height = spec.height;
  size_t texels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
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

void ImageCache::load(const Scene &scene) {
  for (const ImageRef &ref : scene.images) {
    if (images_.count(ref.path)) continue;
    images_.emplace(ref.path,
                    std::make_unique<TextureImage>(readImage(ref.path, linear_, ref.loc)));
  }
}

const TextureImage *ImageCache::find(const std::string &path) const {
  auto it = images_.find(path);
  return it == images_.end() ? nullptr : it->second.get();
}

size_t ImageCache::memoryBytes() const {
  size_t bytes = 0;
  for (const auto &[path, image] : images_) bytes += image->memoryBytes();
  return bytes;
}

} // namespace lray
