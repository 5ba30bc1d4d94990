// Pipeline: render (last stage). See tile_file.h.
#include "render/tile_file.h"

#include "util/scene_error.h"
#include "shading/oiio_library.h"

#include <fmt/format.h>
#include <stb/stb_image.h>

#include <filesystem>
#include <memory>

namespace lray {

namespace fs = std::filesystem;

namespace {

constexpr const char *kFinal = "lray:final", *kFormat = "lray:format", *kEncoding = "lray:encoding",
                     *kRender = "lray:render";

bool formatNamed(const std::string &name, ImageFormat &format) {
  for (ImageFormat f : {ImageFormat::Png, ImageFormat::Tga, ImageFormat::Exr})
    if (formatExtension(f) == name) {
      format = f;
      return true;
    }
  return false;
}

} // namespace

std::string renderFingerprint(const std::string &sceneBytes, const std::string &settings) {
  uint64_t h = 14695981039346656037ull;
  auto add = [&](const std::string &text) {
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    h = (h ^ 0xff) * 1099511628211ull; // a separator no text holds
  };
  add(sceneBytes);
  add(settings);
  return fmt::format("{:016x}", h);
}

PixelWindow tileBand(int index, int count, int width, int height) {
  const int rows = (height + kTileSize - 1) / kTileSize;
  if (count > rows)
    throw SceneError(fmt::format("--tile {}/{}: a frame {} pixels high has {} rows of {}-pixel "
                                 "tiles, so at most {} tiles",
                                 index, count, height, rows, kTileSize, rows));
  const int first = static_cast<int>(static_cast<long>(index) * rows / count);
  const int last = static_cast<int>(static_cast<long>(index + 1) * rows / count);
  return {0, first * kTileSize, width, std::min(height, last * kTileSize)};
}

std::string tileFileName(const std::string &finalName, int index, int count) {
  return fmt::format("{}.tile-{}-of-{}.exr", fs::path(finalName).stem().string(), index, count);
}

std::string cropFileName(const std::string &finalName, const PixelWindow &w) {
  return fmt::format("{}.crop-{}-{}-{}-{}.exr", fs::path(finalName).stem().string(), w.x0, w.y0,
                     w.x1, w.y1);
}

void writeTile(const Film &film, const TileHeader &header, const std::string &path) {
  const PixelWindow &w = header.window;
  FloatWindow image;
  image.fullWidth = film.width();
  image.fullHeight = film.height();
  image.x0 = w.x0;
  image.y0 = w.y0;
  image.width = w.x1 - w.x0;
  image.height = w.y1 - w.y0;
  // The film's EXR channels, cut to the window.
  std::vector<float> all = exrPixels(film, image.channels);
  const size_t nc = image.channels.size();
  image.pixels.reserve(static_cast<size_t>(image.width) * image.height * nc);
  for (int y = w.y0; y < w.y1; ++y) {
    const float *row = all.data() + (static_cast<size_t>(y) * film.width() + w.x0) * nc;
    image.pixels.insert(image.pixels.end(), row, row + static_cast<size_t>(image.width) * nc);
  }
  image.attributes = {{kFinal, header.finalName},
                      {kFormat, formatExtension(header.format)},
                      {kEncoding, header.srgb ? "srgb" : "linear"},
                      {kRender, header.render}};

  writeAtomically(path, "tile", [&](const std::string &tmp) {
    return oiioLibrary().writeFloatWindow(tmp, image);
  });
}

Tile readTile(const std::string &path) {
  FloatWindow image;
  if (std::string why = oiioLibrary().readFloatWindow(path, image); !why.empty())
    throw SceneError("tile '" + path + "': " + why);
  Tile tile;
  TileHeader &h = tile.header;
  std::string format, encoding;
  for (const auto &[name, value] : image.attributes) {
    if (name == kFinal) h.finalName = value;
    else if (name == kFormat) format = value;
    else if (name == kEncoding) encoding = value;
    else if (name == kRender) h.render = value;
  }
  if (h.finalName.empty() || !formatNamed(format, h.format) ||
      (encoding != "srgb" && encoding != "linear"))
    throw SceneError("tile '" + path + "': not a tile written by lray --tile or --crop (no "
                     "frame name, format or encoding in its header)");
  // The frame it names is the one its own file name says, in its format:
  // a tile cannot make lray-merge write any other file.
  const std::string tileName = fs::path(path).filename().string();
  const fs::path finalPath(h.finalName);
  if (finalPath.filename() != finalPath || finalPath.stem().string().empty() ||
      tileName.rfind(finalPath.stem().string() + ".", 0) != 0 ||
      finalPath.extension() != "." + formatExtension(h.format))
    throw SceneError("tile '" + path + "': it names the frame '" + h.finalName +
                     "', which is not its own");
  h.srgb = encoding == "srgb";
  h.fullWidth = image.fullWidth;
  h.fullHeight = image.fullHeight;
  const int64_t x1 = int64_t{image.x0} + image.width, y1 = int64_t{image.y0} + image.height;
  if (h.fullWidth <= 0 || h.fullHeight <= 0 ||
      static_cast<uint64_t>(h.fullWidth) * static_cast<uint64_t>(h.fullHeight) > kMaxTextureTexels)
    throw SceneError("tile '" + path + "': its frame is " + std::to_string(h.fullWidth) + " x " +
                     std::to_string(h.fullHeight) + " pixels, outside the limit of " +
                     std::to_string(kMaxTextureTexels));
  if (image.x0 < 0 || image.y0 < 0 || x1 > h.fullWidth || y1 > h.fullHeight)
    throw SceneError("tile '" + path + "': its pixels lie outside its frame");
  h.window = {image.x0, image.y0, static_cast<int>(x1), static_cast<int>(y1)};
  const auto &ch = image.channels;
  const size_t nc = ch.size();
  auto at = [&](const char *name) -> int {
    for (size_t i = 0; i < nc; ++i)
      if (ch[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int r = at("R"), g = at("G"), b = at("B"), err = at("Error"), count = at("SampleCount");
  if (r < 0 || g < 0 || b < 0 || err < 0 || count < 0)
    throw SceneError("tile '" + path + "': missing one of the channels R, G, B, Error, SampleCount");
  const int z = at("Z"), nx = at("N.X"), ny = at("N.Y"), nz = at("N.Z"), ar = at("Albedo.R"),
            ag = at("Albedo.G"), ab = at("Albedo.B");
  const bool aovs = z >= 0 && nx >= 0 && ny >= 0 && nz >= 0 && ar >= 0 && ag >= 0 && ab >= 0;
  tile.film = Film(image.width, image.height);
  if (aovs) tile.film.enableAovs();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float *p = &image.pixels[(static_cast<size_t>(y) * image.width + x) * nc];
      tile.film.set(x, y, {p[r], p[g], p[b]});
      tile.film.setError(x, y, p[err]);
      const float n = p[count];
      tile.film.setSampleCount(x, y, n >= 0 && n <= 4294967040.f ? static_cast<uint32_t>(n) : 0);
      if (aovs) {
        Film::Aov &a = tile.film.aov(x, y);
        a = {p[z], {p[nx], p[ny], p[nz]}, {p[ar], p[ag], p[ab]}};
      }
    }
  return tile;
}

bool completeTile(const std::string &path, const TileHeader &expected) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  try {
    const TileHeader h = readTile(path).header;
    return h.finalName == expected.finalName && h.format == expected.format &&
           h.srgb == expected.srgb && h.fullWidth == expected.fullWidth &&
           h.fullHeight == expected.fullHeight && h.window == expected.window &&
           h.render == expected.render;
  } catch (const SceneError &) {
    return false;
  }
}

bool completeImage(const std::string &path, ImageFormat format, int width, int height) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  if (format == ImageFormat::Exr) {
    FloatWindow image;
    return oiioLibrary().readFloatWindow(path, image).empty() && image.width == width &&
           image.height == height;
  }
  int w = 0, h = 0, channels = 0;
  if (!stbi_info(path.c_str(), &w, &h, &channels) || w != width || h != height) return false;
  // Decoded in full: a file cut short fails here.
  std::unique_ptr<unsigned char, void (*)(void *)> pixels(
      stbi_load(path.c_str(), &w, &h, &channels, 0), &stbi_image_free);
  return pixels != nullptr;
}

} // namespace lray
