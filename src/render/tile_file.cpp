// Pipeline: render (last stage). See tile_file.h.
#include "render/tile_file.h"

#include "util/scene_error.h"
#include "shading/oiio_library.h"

#include <fmt/format.h>
#include <stb/stb_image.h>

#include <cstdio>
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

/// The most channels an LRay tile has: R, G, B, Error, SampleCount, three
/// of variance and the seven AOV channels.
constexpr size_t kMaxTileChannels = 15;

TileHeader readTileHeader(const std::string &path, FloatWindow &image) {
  if (std::string why = oiioLibrary().readFloatWindow(path, image, false); !why.empty())
    throw SceneError("tile '" + path + "': " + why);
  TileHeader h;
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
  // Its own file name must be the one lray gives a tile (or crop) of the
  // frame it names, in that frame's folder: so it cannot make lray-merge
  // write (and then remove) any other file, its own included.
  const std::string name = fs::path(path).filename().string();
  const fs::path finalPath(h.finalName);
  bool ownName = finalPath.filename() == finalPath && !finalPath.stem().string().empty() &&
                 finalPath.extension() == "." + formatExtension(h.format) &&
                 name == cropFileName(h.finalName, h.window);
  const std::string prefix = finalPath.stem().string() + ".tile-";
  if (!ownName && name.rfind(prefix, 0) == 0) {
    int index = -1, count = -1;
    char end = 0;
    if (std::sscanf(name.c_str() + prefix.size(), "%6d-of-%6d.ex%c", &index, &count, &end) == 3)
      ownName = index >= 0 && index < count && name == tileFileName(h.finalName, index, count) &&
                finalPath.filename() == finalPath &&
                finalPath.extension() == "." + formatExtension(h.format);
  }
  if (!ownName)
    throw SceneError("tile '" + path + "': it names the frame '" + h.finalName +
                     "', which is not its own (lray calls that frame's tiles " +
                     finalPath.stem().string() + ".tile-I-of-N.exr)");
  if (image.channels.size() > kMaxTileChannels)
    throw SceneError("tile '" + path + "': " + std::to_string(image.channels.size()) +
                     " channels, more than an LRay tile has (" +
                     std::to_string(kMaxTileChannels) + ")");
  return h;
}

Tile readTile(const std::string &path) {
  FloatWindow image;
  Tile tile;
  tile.header = readTileHeader(path, image);
  if (std::string why = oiioLibrary().readFloatWindow(path, image, true); !why.empty())
    throw SceneError("tile '" + path + "': " + why);
  const TileHeader &h = tile.header;
  if (image.x0 != h.window.x0 || image.y0 != h.window.y0 ||
      image.x0 + image.width != h.window.x1 || image.y0 + image.height != h.window.y1)
    throw SceneError("tile '" + path + "': it changed while it was read");
  const auto &ch = image.channels;
  const size_t nc = ch.size();
  auto at = [&](const char *name) -> int {
    for (size_t i = 0; i < nc; ++i)
      if (ch[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int r = at("R"), g = at("G"), b = at("B"), err = at("Error"), count = at("SampleCount");
  if (r < 0 || g < 0 || b < 0 || err < 0 || count < 0)
    throw SceneError("tile '" + path +
                     "': missing one of the channels R, G, B, Error, SampleCount");
  const int vr = at("Variance.R"), vg = at("Variance.G"), vb = at("Variance.B");
  const bool variance = vr >= 0 && vg >= 0 && vb >= 0;
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
      if (variance) tile.film.setVariance(x, y, {p[vr], p[vg], p[vb]});
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
    FloatWindow image;
    const TileHeader h = readTileHeader(path, image);
    const bool same = h.finalName == expected.finalName && h.format == expected.format &&
                      h.srgb == expected.srgb && h.fullWidth == expected.fullWidth &&
                      h.fullHeight == expected.fullHeight && h.window == expected.window &&
                      h.render == expected.render;
    if (!same) return false;
    readTile(path); // decoded in full only when it is the tile wanted: a file cut short fails
    return true;
  } catch (const SceneError &) {
    return false;
  }
}

bool completeImage(const std::string &path, ImageFormat format, int width, int height) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  if (format == ImageFormat::Exr) {
    // The header first: a huge file of another size is never decoded.
    FloatWindow image;
    if (!oiioLibrary().readFloatWindow(path, image, false).empty() || image.width != width ||
        image.height != height)
      return false;
    return oiioLibrary().readFloatWindow(path, image, true).empty();
  }
  int w = 0, h = 0, channels = 0;
  if (!stbi_info(path.c_str(), &w, &h, &channels) || w != width || h != height) return false;
  // Decoded in full: a file cut short fails here.
  std::unique_ptr<unsigned char, void (*)(void *)> pixels(
      stbi_load(path.c_str(), &w, &h, &channels, 0), &stbi_image_free);
  return pixels != nullptr;
}

} // namespace lray
