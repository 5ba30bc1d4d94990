// Pipeline: shading. Texture images decoded once per path per render
// through OpenImageIO and shared, read-only, by all frames and threads.
#pragma once

#include "scene/scene.h"
#include "shading/pigments/texture_image.h"

#include <cstddef>
#include <memory>
#include <string>
#include <unordered_map>

namespace lray {

/// Decoded texture images keyed by path. load() runs between frames (not
/// thread-safe); find() and the images themselves are read-only during
/// rendering.
class ImageCache {
public:
  /// linearWorkflow: 8-bit images are decoded from sRGB (--linear);
  /// otherwise they are used as stored (value / 255). Float formats are
  /// always used as is.
  explicit ImageCache(bool linearWorkflow);

  /// Loads every Scene::images entry not yet loaded; throws SceneError
  /// naming the path (prefixed with ImageRef::loc) when it is missing or
  /// unreadable, or would take the frame past its render memory budget
  /// (Scene::memory, charged with every image the frame uses).
  void load(Scene &scene);

  /// The image loaded for `path`, or nullptr.
  const TextureImage *find(const std::string &path) const;

  size_t size() const { return images_.size(); }
  size_t memoryBytes() const;

  /// Decodes one file (any format OpenImageIO reads); throws SceneError.
  /// Charged to `budget` before decoding (null: none).
  static TextureImage readImage(const std::string &path, bool linearWorkflow,
                                const SourceLocation &loc = {}, MemoryBudget *budget = nullptr);

private:
  bool linear_;
  std::unordered_map<std::string, std::unique_ptr<TextureImage>> images_;
};

} // namespace lray
