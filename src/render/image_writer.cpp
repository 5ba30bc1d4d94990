// Pipeline: render (last stage). OpenImageIO output with temp-file + rename.
#include "render/image_writer.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace lray {

namespace fs = std::filesystem;

std::string formatExtension(ImageFormat format) {
  switch (format) {
  case ImageFormat::Png: return "png";
  case ImageFormat::Tga: return "tga";
  case ImageFormat::Exr: return "exr";
  }
  return "png";
}

uint8_t quantize8(float value, bool srgb) {
  float v = std::isnan(value) ? 0.f : std::clamp(value, 0.f, 1.f);
  if (srgb) v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.f, 1.f) * 255.f));
}

std::vector<uint8_t> quantizeFilm(const Film &film, bool srgb) {
  const std::vector<float> &src = film.data();
  std::vector<uint8_t> out(src.size());
  std::transform(src.begin(), src.end(), out.begin(), [srgb](float v) { return quantize8(v, srgb); });
  return out;
}

void writeImage(const Film &film, const std::string &path, ImageFormat format, bool srgb) {
  static std::atomic<unsigned> counter{0};
  fs::path finalPath(path);
  // Keep the extension last: OpenImageIO picks the writer from it.
  fs::path tmpPath = finalPath.parent_path() /
                     ("." + finalPath.stem().string() + ".tmp" + std::to_string(getpid()) + "_" +
                      std::to_string(counter++) + finalPath.extension().string());

  auto fail = [&](const std::string &why) {
    std::error_code ec;
    fs::remove(tmpPath, ec);
    throw std::runtime_error("cannot write image '" + path + "': " + why);
  };

  auto out = OIIO::ImageOutput::create(tmpPath.string());
  if (!out) fail(OIIO::geterror());
  bool ok;
  if (format == ImageFormat::Exr) {
    OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::FLOAT);
    if (!out->open(tmpPath.string(), spec)) fail(out->geterror());
    ok = out->write_image(OIIO::TypeDesc::FLOAT, film.data().data());
  } else {
    OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::UINT8);
    // Default mode writes values as computed (SPEC 1), with no colour-space tag.
    if (srgb) spec.attribute("oiio:ColorSpace", "sRGB");
    std::vector<uint8_t> bytes = quantizeFilm(film, srgb);
    if (!out->open(tmpPath.string(), spec)) fail(out->geterror());
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!ok) fail(out->geterror());
  if (!out->close()) fail(out->geterror());
  std::error_code ec;
  fs::rename(tmpPath, finalPath, ec);
  if (ec) fail(ec.message());
}

} // namespace lray
