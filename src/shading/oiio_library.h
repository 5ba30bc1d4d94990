// Pipeline: shading. OpenImageIO, loaded on first use: its ~260 shared
// libraries took a quarter of a second to load and relocate at every start
// of `lray`, even for scenes without image textures writing PNG or TGA
// (which render/image_writer.cpp writes through libpng and stb). The module
// (oiio_module.cpp, liblray_oiio.so) holds all of LRay's OpenImageIO code.
#pragma once

#include "util/memory_budget.h"
#include "util/scene_error.h"
#include "shading/pigments/texture_image.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lray {

/// Largest texture decoded (width * height): 2^28 texels, 3 GiB as float
/// RGB, a 16384 x 16384 image.
inline constexpr size_t kMaxTextureTexels = size_t{1} << 28;

/// The error for an image whose header claims more than kMaxTextureTexels
/// (both decoders check the header before allocating).
inline SceneError textureTooLarge(const SourceLocation &loc, const std::string &path,
                                  uint64_t width, uint64_t height) {
  return SceneError(loc, "ImagePigment2D: image '" + path + "' is " + std::to_string(width) +
                             " x " + std::to_string(height) + " texels, more than the limit of " +
                             std::to_string(kMaxTextureTexels));
}

/// Charges a texture's decoding against `budget` (null: none) before
/// anything is allocated for it: the decoder's buffer of all `channels` and
/// the RGB floats kept. Returns the buffer's bytes, to release once decoded
/// (the kept floats stay charged for the frame).
inline uint64_t chargeTexture(MemoryBudget *budget, uint64_t texels, uint64_t channels,
                              uint64_t bytesPerChannel, const std::string &path,
                              const SourceLocation &loc) {
  const uint64_t buffer = texels * channels * bytesPerChannel;
  if (budget)
    budget->charge(buffer + texels * 3 * sizeof(float), "ImagePigment2D: image '" + path + "'",
                   loc);
  return buffer;
}

/// A float image that is a window of a larger frame (an EXR's data window
/// inside its display window), with string attributes: a tile of a frame
/// rendered with --tile or --crop (render/tile_file.h).
struct FloatWindow {
  int fullWidth = 0, fullHeight = 0;          ///< the frame (display window)
  int x0 = 0, y0 = 0, width = 0, height = 0;  ///< the pixels held (data window)
  std::vector<std::string> channels;
  std::vector<float> pixels; ///< width * height * channels.size(), interleaved, row y0 first
  std::vector<std::pair<std::string, std::string>> attributes;
};

/// The module's entry points (C++ types: it is built with the same
/// compiler and flags, and loaded into the same process).
struct OiioLibrary {
  /// ImageCache::readImage's contract: any format OpenImageIO reads,
  /// SceneError naming the path on failure.
  /// The decoding is charged to `budget` (null: none) first, chargeTexture.
  TextureImage (*readImage)(const std::string &path, bool linearWorkflow,
                            const SourceLocation &loc, MemoryBudget *budget);
  /// Writes width x height pixels of channels.size() interleaved floats
  /// (row 0 = top), the channels named as given, to `path` in the format of
  /// its extension; "" on success, else the reason.
  std::string (*writeFloat)(const std::string &path, int width, int height,
                            const std::vector<std::string> &channels, const float *pixels);
  /// Writes `image` as an EXR with its windows and attributes; "" or why not.
  std::string (*writeFloatWindow)(const std::string &path, const FloatWindow &image);
  /// Reads an EXR written by writeFloatWindow (no other format is tried): its
  /// header, and with `withPixels` its pixels; "" or why not. Refuses a
  /// header claiming more than kMaxTextureTexels pixels or 64 channels
  /// before allocating.
  std::string (*readFloatWindow)(const std::string &path, FloatWindow &image, bool withPixels);
};

/// The module, loaded once (thread-safe); throws std::runtime_error naming
/// the module file when it cannot be loaded.
const OiioLibrary &oiioLibrary();

/// Whether the module has been loaded in this process (for tests).
bool oiioLibraryLoaded();

} // namespace lray
