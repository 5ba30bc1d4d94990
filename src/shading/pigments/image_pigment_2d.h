// Pipeline: shading. ImagePigment2D (lua/README.md, "Textures, finishes and pigments"): an image
// looked up at the map's (s, t), repeating every 1 (shading/pigments/texture_image.h); black when
// the image was not loaded.
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct ImagePigment2D {
  static constexpr const char *kName = "ImagePigment2D";
  static constexpr int kDimensions = 2;

  uint32_t image = 0; ///< index into Scene::images

  Color evaluate(const PigmentContext &c) const;
};

} // namespace lray
