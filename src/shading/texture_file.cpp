// Pipeline: shading. See texture_file.h.
#include "shading/texture_file.h"

#include "shading/oiio_library.h"
#include "shading/texel_convert.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <memory>

namespace lray {

namespace {

enum class Kind { Other, Png, Tga };

/// PNG by its signature; TGA (which has none) by its extension and a
/// header stb and OpenImageIO read alike: colour-mapped, true-colour or
/// grey, 8, 24 or 32 bits per pixel.
/// (A PNG's size is read from its IHDR chunk into `pngWidth` x `pngHeight`:
/// stb refuses huge images with a message that does not say why.)
Kind kindOf(const std::string &path, uint64_t &pngWidth, uint64_t &pngHeight) {
  std::unique_ptr<FILE, int (*)(FILE *)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return Kind::Other;
  unsigned char header[24] = {};
  const size_t got = std::fread(header, 1, sizeof header, file.get());
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got >= 8 && std::memcmp(header, kPng, 8) == 0) {
    auto be32 = [&](int at) {
      return (uint32_t{header[at]} << 24) | (uint32_t{header[at + 1]} << 16) |
             (uint32_t{header[at + 2]} << 8) | uint32_t{header[at + 3]};
    };
    if (got == sizeof header && std::memcmp(header + 12, "IHDR", 4) == 0) {
      pngWidth = be32(16);
      pngHeight = be32(20);
    }
    return Kind::Png;
  }
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".tga" || got < 18) return Kind::Other;
  const int imageType = header[2] & ~8; // bit 3: run-length encoded
  const int depth = header[16];
  // Right-to-left rows (descriptor bit 4) and colour maps whose first
  // entry is not 0 stb reads differently: those go to OpenImageIO.
  if (header[17] & 0x10) return Kind::Other;
  const bool colourMapped =
      imageType == 1 && header[1] == 1 && header[7] == 24 && header[3] == 0 && header[4] == 0;
  const bool trueColour = imageType == 2 && (depth == 24 || depth == 32);
  const bool grey = imageType == 3 && depth == 8;
  return colourMapped || trueColour || grey ? Kind::Tga : Kind::Other;
}

} // namespace

std::optional<TextureImage> decodeEightBitTexture(const std::string &path, bool linearWorkflow,
                                                  const SourceLocation &loc,
                                                  MemoryBudget *budget) {
  uint64_t pngWidth = 0, pngHeight = 0;
  const Kind kind = kindOf(path, pngWidth, pngHeight);
  if (kind == Kind::Other) return std::nullopt;
  if (pngWidth * pngHeight > kMaxTextureTexels)
    throw textureTooLarge(loc, path, pngWidth, pngHeight);
  // A PNG that stb cannot read is reported here: OpenImageIO's libpng
  // would print its own "libpng error" line before LRay's message.
  auto broken = [&]() -> std::optional<TextureImage> {
    if (kind != Kind::Png) return std::nullopt; // OpenImageIO names what is wrong
    throw SceneError(loc, "ImagePigment2D: cannot decode image '" + path + "' (" +
                              stbi_failure_reason() + ")");
  };
  int width = 0, height = 0, channels = 0;
  if (!stbi_info(path.c_str(), &width, &height, &channels) || width <= 0 || height <= 0)
    return broken();
  if (kind == Kind::Png && stbi_is_16_bit(path.c_str())) return std::nullopt;
  const size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (texels > kMaxTextureTexels) throw textureTooLarge(loc, path, width, height);
  const uint64_t buffer = chargeTexture(budget, texels, channels, 1, path, loc);
  std::unique_ptr<stbi_uc, void (*)(void *)> data(
      stbi_load(path.c_str(), &width, &height, &channels, 0), &stbi_image_free);
  if (!data) return broken();
  TextureImage image;
  image.width = width;
  image.height = height;
  const std::array<float, 256> lut = eightBitTable(linearWorkflow);
  toRgb(data.get(), channels, texels, image.rgb, [&](stbi_uc v) { return lut[v]; });
  if (budget) budget->release(buffer);
  return image;
}

} // namespace lray
