// Pipeline: render (last stage). A window of a frame rendered on its own
// (--tile, --crop: a render farm's task) and written as an EXR tile: the
// film's float channels for the window, the frame's size as the display
// window, and what lray-merge needs to write the frame exactly as one
// process would have (its file name, format and encoding). Merged tiles give
// the same bytes as a render of the whole frame.
#pragma once

#include "render/film.h"
#include "render/frame_settings.h"
#include "render/image_writer.h"

#include <string>
#include <vector>

namespace lray {

struct FloatWindow; // shading/oiio_library.h

/// What a tile says about the frame it belongs to.
struct TileHeader {
  std::string finalName; ///< the frame's file name, no folder (e.g. "ring0003.png")
  ImageFormat format = ImageFormat::Png;
  bool srgb = false;     ///< --linear: 8-bit outputs are sRGB-encoded
  int fullWidth = 0, fullHeight = 0;
  PixelWindow window;
  /// What the frame was rendered from and with (renderFingerprint): tiles
  /// of one frame must agree, or they are not of one render.
  std::string render;
};

/// A fingerprint of a render's inputs: the scene file's bytes and every
/// setting that changes pixels (FNV-1a, hex). Files the scene reads (OBJ,
/// images) are not in it.
std::string renderFingerprint(const std::string &sceneBytes, const std::string &settings);

/// Band `index` (0-based) of `count` bands of whole 16-pixel tile rows of a
/// width x height frame. Throws SceneError when count exceeds the rows.
PixelWindow tileBand(int index, int count, int width, int height);

/// The tile file's name for a frame file: "ring0003.tile-1-of-4.exr", or
/// with an explicit window "ring0003.crop-0-0-64-48.exr".
std::string tileFileName(const std::string &finalName, int index, int count);
std::string cropFileName(const std::string &finalName, const PixelWindow &window);

/// Writes the window of `film` as a tile (atomically: a temporary file
/// renamed over `path`). Throws std::runtime_error naming the path.
void writeTile(const Film &film, const TileHeader &header, const std::string &path);

/// A tile read back: its header and its pixels as a film of the window's
/// size (the same channels; AOVs when it has them). Throws SceneError
/// naming the path when it is not a readable LRay tile.
struct Tile {
  TileHeader header;
  Film film{0, 0};
};
Tile readTile(const std::string &path);

/// readTile's checks on the header alone, before any pixel is decoded: an
/// LRay tile's attributes, a frame within kMaxTextureTexels, a window inside
/// it, at most LRay's channels, and a file name that is the one lray gives
/// that window of that frame. `image` gets the header (no pixels).
TileHeader readTileHeader(const std::string &path, FloatWindow &image);

/// Whether `path` is a complete image of `width` x `height` pixels in
/// `format` (fully decoded: a truncated file is not): --skip-existing.
bool completeImage(const std::string &path, ImageFormat format, int width, int height);

/// Whether `path` is a complete tile with exactly this header (the same
/// frame, format, encoding, size, window and render): --skip-existing.
bool completeTile(const std::string &path, const TileHeader &expected);

} // namespace lray
