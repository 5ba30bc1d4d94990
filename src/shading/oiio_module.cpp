// Pipeline: shading (a module of its own). Everything of LRay that uses
// OpenImageIO: decoding texture images and writing float (EXR) images.
// Built as liblray_oiio.so and loaded by oiio_library.cpp on first use, so
// the renderer does not load OpenImageIO's 260 libraries when a scene has
// no image texture and the output is PNG or TGA.
#include "shading/oiio_library.h"
#include "shading/exr_header.h"
#include "shading/texel_convert.h"

#include <sys/resource.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {
namespace {

TextureImage readImage(const std::string &path, bool linearWorkflow, const SourceLocation &loc,
                       MemoryBudget *budget) {
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
  if (texels > kMaxTextureTexels) throw textureTooLarge(loc, path, spec.width, spec.height);
  // Every channel is decoded (a 16-channel EXR holds 16 floats a texel).
  const bool eightBit = spec.format == OIIO::TypeDesc::UINT8;
  const uint64_t buffer =
      chargeTexture(budget, texels, nch, eightBit ? 1 : sizeof(float), path, loc);
  TextureImage image;
  image.width = spec.width;
  image.height = spec.height;
  bool ok = false;
  if (eightBit) {
    std::vector<uint8_t> data(texels * nch);
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, data.data());
    const std::array<float, 256> lut = eightBitTable(linearWorkflow);
    if (ok) toRgb(data.data(), nch, texels, image.rgb, [&](uint8_t v) { return lut[v]; });
  } else {
    std::vector<float> data(texels * nch);
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, data.data());
    // A NaN or Inf texel would poison every pixel that filters it.
    auto finite = [](float v) { return std::isfinite(v) ? v : 0.0f; };
    if (ok) toRgb(data.data(), nch, texels, image.rgb, finite);
  }
  if (!ok) {
    std::string why = in->geterror();
    throw SceneError(loc, "ImagePigment2D: cannot decode image '" + path + "'" +
                              (why.empty() ? std::string() : " (" + why + ")"));
  }
  in->close();
  if (budget) budget->release(buffer);
  return image;
}

/// OpenImageIO's reason, or ours where it gave none (it fails silently
/// when it runs out of memory, as under an address-space limit).
std::string writeError(std::string why) {
  if (!why.empty()) return why;
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    return "OpenImageIO could not write it (out of memory under this process's address-space "
           "limit, ulimit -v?)";
  return "OpenImageIO could not write it";
}

std::string writeFloat(const std::string &path, int width, int height,
                       const std::vector<std::string> &channels, const float *pixels) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return writeError(OIIO::geterror());
  OIIO::ImageSpec spec(width, height, static_cast<int>(channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channels;
  // No time stamp (OpenImageIO would write the current time as capDate):
  // the same film gives the same bytes, so a frame stitched from a farm's
  // tiles is byte-identical to one rendered whole.
  spec.attribute("DateTime", "");
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels) || !out->close())
    return writeError(out->geterror());
  return {};
}

std::string writeFloatWindow(const std::string &path, const FloatWindow &image) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return writeError(OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, static_cast<int>(image.channels.size()),
                       OIIO::TypeDesc::FLOAT);
  spec.x = image.x0;
  spec.y = image.y0;
  spec.full_x = 0;
  spec.full_y = 0;
  spec.full_width = image.fullWidth;
  spec.full_height = image.fullHeight;
  spec.channelnames = image.channels;
  spec.attribute("DateTime", ""); // as writeFloat
  for (const auto &[name, value] : image.attributes) spec.attribute(name, value);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) ||
      !out->close())
    return writeError(out->geterror());
  return {};
}

std::string readFloatWindow(const std::string &path, FloatWindow &image, bool withPixels) {
  // The header's claims against the file's size before OpenEXR sizes its
  // buffers by them (shading/exr_header.h).
  if (std::string why = checkExrHeader(path, {kMaxTextureTexels, 64}); !why.empty()) return why;
  // OpenEXR's reader only: ImageInput::open would try every format
  // OpenImageIO knows on a file that is not a valid EXR (FFmpeg, LibRaw,
  // DICOM...), a slow and needless surface for a crafted tile.
  auto in = OIIO::ImageInput::create("openexr");
  OIIO::ImageSpec opened;
  if (!in || !in->open(path, opened)) {
    std::string why = in ? in->geterror() : OIIO::geterror();
    return why.empty() ? std::string("cannot open it as an EXR") : why;
  }
  const OIIO::ImageSpec &spec = in->spec();
  const size_t pixels = static_cast<size_t>(std::max(spec.width, 0)) * std::max(spec.height, 0);
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return "it is empty";
  if (pixels > kMaxTextureTexels || spec.nchannels > 64) return "its header claims an absurd size";
  image.fullWidth = spec.full_width;
  image.fullHeight = spec.full_height;
  image.x0 = spec.x;
  image.y0 = spec.y;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.channelnames;
  image.attributes.clear();
  for (const OIIO::ParamValue &p : spec.extra_attribs)
    if (p.type() == OIIO::TypeDesc::STRING)
      image.attributes.emplace_back(p.name().string(), p.get_string());
  image.pixels.clear();
  if (!withPixels) return {};
  image.pixels.resize(pixels * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    std::string why = in->geterror();
    return why.empty() ? std::string("cannot decode it") : why;
  }
  in->close();
  return {};
}

} // namespace

} // namespace lray

extern "C" const lray::OiioLibrary *lray_oiio_library() {
  static const lray::OiioLibrary library{&lray::readImage, &lray::writeFloat,
                                         &lray::writeFloatWindow, &lray::readFloatWindow};
  return &library;
}
