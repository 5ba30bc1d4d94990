// Pipeline: shading. The cache of decoded texture images; decoding itself is
// stb_image's for 8-bit PNG and TGA (texture_file.h), else OpenImageIO's,
// in the module oiio_module.cpp.
#include "shading/image_cache.h"

#include "shading/oiio_library.h"
#include "shading/texture_file.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {

ImageCache::ImageCache(bool linearWorkflow) : linear_(linearWorkflow) {}

TextureImage ImageCache::readImage(const std::string &path, bool linearWorkflow,
                                   const SourceLocation &loc, MemoryBudget *budget) {
  if (std::optional<TextureImage> image = decodeEightBitTexture(path, linearWorkflow, loc, budget))
    return std::move(*image);
  return oiioLibrary().readImage(path, linearWorkflow, loc, budget);
}

void ImageCache::load(Scene &scene) {
  for (const ImageRef &ref : scene.images) {
    auto it = images_.find(ref.path);
    if (it != images_.end()) {
      scene.memory.charge(it->second->memoryBytes(), "ImagePigment2D: image '" + ref.path + "'",
                          ref.loc);
      continue;
    }
    images_.emplace(ref.path, std::make_unique<TextureImage>(
                                  readImage(ref.path, linear_, ref.loc, &scene.memory)));
  }
}

const TextureImage *ImageCache::find(const std::string &path) const {
  auto it = images_.find(path);
  return it == images_.end() ? nullptr : it->second.get();
}

size_t ImageCache::memoryBytes() const {
  size_t bytes = 0;
  for (const auto &[path, image] : images_) bytes += image->memoryBytes();
  return bytes;
}

} // namespace lray
