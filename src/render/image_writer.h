// Pipeline: render (last stage). Writes a Film as PNG (libpng), TGA (stb)
// or EXR (OpenImageIO), never leaving a truncated file under the final name.
#pragma once

#include "render/film.h"
#include "render/output_file.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lray {

enum class ImageFormat { Png, Tga, Exr };

/// "png" / "tga" / "exr"; also the file extension.
std::string formatExtension(ImageFormat format);

/// 8-bit value written for a linear-light value: clamped to [0,1] and rounded;
/// with `srgb` the value is first encoded with the sRGB transfer curve.
uint8_t quantize8(float value, bool srgb);

/// The 8-bit RGB bytes an LDR file of this film holds (row 0 = top).
std::vector<uint8_t> quantizeFilm(const Film &film, bool srgb);

/// The channels an EXR of `film` holds, interleaved, and their names:
/// R, G, B, Error (the pixel's error estimate, render/pixel_error.h),
/// SampleCount, Variance.R, Variance.G, Variance.B (the variance of the
/// pixel's value, Film::variance), then with AOVs Z, N.X, N.Y, N.Z, Albedo.R, Albedo.G,
/// Albedo.B (the names of pbrt-v4's GBufferFilm).
std::vector<float> exrPixels(const Film &film, std::vector<std::string> &channels);

/// The PNG file of `film` in memory, as writeImage would write it (the
/// live preview serves it).
std::vector<uint8_t> encodePng(const Film &film, bool srgb);

/// Writes `film` to `path` in `format`: PNG/TGA 8 bits per channel (clamped,
/// rounded; sRGB-encoded when `srgb`), EXR 32-bit float unclamped. Writes a
/// complete file or none (render/output_file.h). Throws SceneError naming
/// the path and the reason on failure.
void writeImage(const Film &film, const std::string &path, ImageFormat format, bool srgb);

} // namespace lray
