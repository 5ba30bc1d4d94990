// Pipeline: shading. See texture_file.h.
#include "shading/texture_file.h"

#include "shading/oiio_library.h"
#include "shading/texel_convert.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <memory>

namespace lray {

namespace {

enum class Kind { Other, Png, Tga };

/// PNG by its signature; TGA (which has none) by its extension and a
/// header stb and OpenImageIO read alike: colour-mapped, true-colour or
/// grey, 8, 24 or 32 bits per pixel.
Kind kindOf(const std::string &path) {
  std::unique_ptr<FILE, int (*)(FILE *)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return Kind::Other;
  unsigned char header[18] = {};
  const size_t got = std::fread(header, 1, sizeof header, file.get());
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got >= 8 && std::memcmp(header, kPng, 8) == 0) return Kind::Png;
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".tga" || got < 18) return Kind::Other;
  const int imageType = header[2] & ~8; // bit 3: run-length encoded
  const int depth = header[16];
  const bool colourMapped = imageType == 1 && header[1] == 1 && header[7] == 24;
  const bool trueColour = imageType == 2 && (depth == 24 || depth == 32);
  const bool grey = imageType == 3 && depth == 8;
  return colourMapped || trueColour || grey ? Kind::Tga : Kind::Other;
}

} // namespace

std::optional<TextureImage> decodeEightBitTexture(const std::string &path, bool linearWorkflow,
                                                  const SourceLocation &loc) {
  const Kind kind = kindOf(path);
  if (kind == Kind::Other) return std::nullopt;
  int width = 0, height = 0, channels = 0;
  if (!stbi_info(path.c_str(), &width, &height, &channels) || width <= 0 || height <= 0)
    return std::nullopt;
  if (kind == Kind::Png && stbi_is_16_bit(path.c_str())) return std::nullopt;
  const size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (texels > kMaxTextureTexels)
    throw SceneError(loc, "ImagePigment2D: image '" + path + "' is " + std::to_string(width) +
                              " x " + std::to_string(height) + " texels, more than the " +
                              "limit of " + std::to_string(kMaxTextureTexels));
  std::unique_ptr<stbi_uc, void (*)(void *)> data(
      stbi_load(path.c_str(), &width, &height, &channels, 0), &stbi_image_free);
  if (!data) return std::nullopt; // OpenImageIO names what is wrong with it
  TextureImage image;
  image.width = width;
  image.height = height;
  const std::array<float, 256> lut = eightBitTable(linearWorkflow);
  toRgb(data.get(), channels, texels, image.rgb, [&](stbi_uc v) { return lut[v]; });
  return image;
}

} // namespace lray
