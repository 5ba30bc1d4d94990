// Pipeline: shading. Pigment evaluation (lua/README.md, "Textures, finishes and pigments"): the
// colour of a surface point before lighting, through the one dispatch on Pigment::pattern
// (pigments/pigment_list.h); no virtual calls, no allocation, no Lua.
#pragma once

#include "scene/scene.h"
#include "shading/pigments/pigment_context.h"

namespace lray {

/// evaluatePigment, with a solid colour (ColorPigment: a floor's, a plain
/// sphere's, most surfaces') read here, without the call and the pattern's
/// dispatch: the same colour.
inline Color pigmentAt(const PigmentTable &table, uint32_t index, const Hit &hit) {
  if (index < table.count)
    if (const auto *solid = std::get_if<ColorPigment>(&table.pigments[index].pattern))
      return solid->color;
  return evaluatePigment(table, index, hit);
}

} // namespace lray
