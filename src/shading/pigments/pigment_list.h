// Pipeline: shading. The one list of pigments: a Pigment's pattern is one
// of these, and evaluatePigment (pigment.cpp) reaches its evaluate through
// std::visit. Each states its dimensions (kDimensions: 0 takes no map, 2 a
// 2-D map, 3 a 3-D one), which the converter reads to pick the default map.
// Adding a pigment: its file in this folder, one entry here, one
// registration in bindings/register_textures.cpp (README.md, "Adding a
// pigment").
#pragma once

#include "shading/pigments/checker_pigment_2d.h"
#include "shading/pigments/checker_pigment_3d.h"
#include "shading/pigments/color_pigment.h"
#include "shading/pigments/image_pigment_2d.h"
#include "shading/pigments/marble_pigment_3d.h"
#include "shading/pigments/wood_pigment_3d.h"

#include <variant>

namespace lray {

using PigmentPattern = std::variant<ColorPigment, CheckerPigment2D, CheckerPigment3D,
                                    MarblePigment3D, WoodPigment3D, ImagePigment2D>;

/// The Lua class name of a pattern ("ColorPigment", ...).
inline const char *pigmentName(const PigmentPattern &p) {
  return std::visit([](const auto &k) { return std::decay_t<decltype(k)>::kName; }, p);
}

/// 0, 2 or 3: what texture map the pattern takes.
inline int pigmentDimensions(const PigmentPattern &p) {
  return std::visit([](const auto &k) { return std::decay_t<decltype(k)>::kDimensions; }, p);
}

} // namespace lray
