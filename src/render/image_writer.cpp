// Pipeline: render (last stage). PNG through libpng, TGA through stb, EXR
// through OpenImageIO (loaded only then: shading/oiio_library.h); always a
// temporary file renamed over the final name.
#include "render/image_writer.h"

#include "render/srgb_bytes.h"
#include "shading/oiio_library.h"
#include "util/scene_error.h"

#include <png.h>
#include <stb/stb_image_write.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <csetjmp>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>

namespace lray {

std::string formatExtension(ImageFormat format) {
  switch (format) {
  case ImageFormat::Png: return "png";
  case ImageFormat::Tga: return "tga";
  case ImageFormat::Exr: return "exr";
  }
  return "png";
}

uint8_t quantize8(float value, bool srgb) {
  return srgb ? srgbByte(value) : round255(unitClamp(value));
}

std::vector<uint8_t> quantizeFilm(const Film &film, bool srgb) {
  const auto &src = film.data();
  std::vector<uint8_t> out(src.size());
  // In parallel: a frame's values are independent, and the writing that
  // follows is on one thread.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, src.size(), size_t{1} << 16),
                    [&](const tbb::blocked_range<size_t> &r) {
                      if (srgb) {
                        srgbBytes(&src[r.begin()], &out[r.begin()], r.size());
                        return;
                      }
                      for (size_t i = r.begin(); i != r.end(); ++i)
                        out[i] = round255(unitClamp(src[i])); // quantize8(src[i], false)
                    });
  return out;
}

namespace {

/// libpng's output: this memory buffer.
void appendToBuffer(png_structp png, png_bytep data, png_size_t length) {
  auto *out = static_cast<std::vector<uint8_t> *>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}
void flushNothing(png_structp) {}

/// 8-bit RGB rows as a PNG file in `memory`; "" or the reason it failed.
/// With `srgb` the file says its values are sRGB-encoded (an sRGB chunk);
/// without, it carries no colour-space chunk: the values are written as
/// computed.
std::string writePng(int width, int height, const uint8_t *rgb, bool srgb,
                     std::vector<uint8_t> &memory) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::string why;
  // libpng reports errors by longjmp: nothing below owns a destructor.
  if (!png || !info) {
    why = "libpng: out of memory";
  } else if (setjmp(png_jmpbuf(png))) {
    why = "libpng could not encode it";
  } else {
    png_set_write_fn(png, &memory, &appendToBuffer, &flushNothing);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    // Two row filters (SUB, UP) and zlib level 5, not libpng's five filters
    // and level 6: rendered frames come out within a few percent of that
    // size in 0.4 to 0.75 of the time (README.md, "The `lray` command").
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB | PNG_FILTER_UP);
    png_set_compression_level(png, 5);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y)
      png_write_row(png, rgb + static_cast<size_t>(y) * static_cast<size_t>(width) * 3);
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
  return why;
}

} // namespace

std::vector<uint8_t> encodePng(const Film &film, bool srgb) {
  std::vector<uint8_t> bytes = quantizeFilm(film, srgb), png;
  if (std::string why = writePng(film.width(), film.height(), bytes.data(), srgb, png);
      !why.empty())
    throw std::runtime_error("cannot encode the image as PNG: " + why);
  return png;
}

std::vector<float> exrPixels(const Film &film, std::vector<std::string> &channels) {
  channels = {"R", "G", "B", "Error", "SampleCount", "Variance.R", "Variance.G", "Variance.B"};
  if (film.hasAovs())
    for (const char *name : {"Z", "N.X", "N.Y", "N.Z", "Albedo.R", "Albedo.G", "Albedo.B"})
      channels.push_back(name);
  std::vector<float> pixels;
  pixels.reserve(film.pixels() * channels.size());
  for (int y = 0; y < film.height(); ++y) {
    for (int x = 0; x < film.width(); ++x) {
      const Color c = film.get(x, y), v = film.variance(x, y);
      pixels.insert(pixels.end(),
                    {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b),
                     film.error(x, y), static_cast<float>(film.sampleCount(x, y)),
                     static_cast<float>(v.r), static_cast<float>(v.g), static_cast<float>(v.b)});
      if (film.hasAovs()) {
        const Film::Aov &a = film.aov(x, y);
        pixels.insert(pixels.end(), {a.z, a.n[0], a.n[1], a.n[2], a.albedo[0], a.albedo[1],
                                     a.albedo[2]});
      }
    }
  }
  return pixels;
}

void writeImage(const Film &film, const std::string &path, ImageFormat format, bool srgb) {
  if (format == ImageFormat::Exr) {
    writeAtomically(path, "image", [&](const std::string &tmp) -> std::string {
      std::vector<std::string> channels;
      std::vector<float> pixels = exrPixels(film, channels);
      return oiioLibrary().writeFloat(tmp, film.width(), film.height(), channels, pixels.data());
    });
    return;
  }
  // PNG and TGA are encoded in memory, so that every write of the file
  // itself is checked (stb ignores its write errors; libpng's FILE output
  // reports them without the reason).
  std::vector<uint8_t> bytes;
  if (format == ImageFormat::Png) {
    bytes = encodePng(film, srgb);
  } else {
    const std::vector<uint8_t> rgb = quantizeFilm(film, srgb);
    auto append = [](void *out, void *data, int size) {
      auto *v = static_cast<std::vector<uint8_t> *>(out);
      v->insert(v->end(), static_cast<uint8_t *>(data), static_cast<uint8_t *>(data) + size);
    };
    if (!stbi_write_tga_to_func(append, &bytes, film.width(), film.height(), 3, rgb.data()))
      throw SceneError("cannot encode the image '" + path + "' as TGA");
  }
  writeOutputFile(path, "image",
                  std::string_view(reinterpret_cast<const char *>(bytes.data()), bytes.size()));
}

} // namespace lray
