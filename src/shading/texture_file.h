// Pipeline: shading. Decodes the lossless 8-bit formats most scenes use for
// textures (PNG, and 8/24/32-bit TGA) with stb_image, without loading
// OpenImageIO: loading it costs more per run than rendering a small frame
// (bench/README.md, start-up). Anything else (other formats, 16-bit PNG, a TGA stb cannot
// decode) is left to OpenImageIO, which gives the same texels for what
// both read; a broken PNG is reported here.
#pragma once

#include "util/memory_budget.h"
#include "util/scene_error.h"
#include "shading/pigments/texture_image.h"

#include <optional>
#include <string>

namespace lray {

/// The texture at `path` if it is an 8-bit PNG or TGA that stb decodes,
/// else nothing. Throws SceneError (at `loc`) when its header claims more
/// than kMaxTextureTexels, before allocating anything, and for a PNG that
/// cannot be decoded. The decoding is charged to `budget` first (null:
/// none; oiio_library.h chargeTexture).
std::optional<TextureImage> decodeEightBitTexture(const std::string &path, bool linearWorkflow,
                                                  const SourceLocation &loc,
                                                  MemoryBudget *budget = nullptr);

} // namespace lray
