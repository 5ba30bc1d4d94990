// Pipeline: shading. ColorPigment (lua/README.md, "Textures, finishes and pigments"): one colour
// everywhere; no map.
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct ColorPigment {
  static constexpr const char *kName = "ColorPigment";
  static constexpr int kDimensions = 0; ///< takes no texture map

  Color color{1, 1, 1};

  Color evaluate(const PigmentContext &) const { return color; }
};

} // namespace lray
