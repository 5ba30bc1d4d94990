// Pipeline: shading. Pigment evaluation (lua/README.md, "Textures, finishes and pigments"): the
// colour of a surface point before lighting, through the one dispatch on Pigment::pattern
// (pigments/pigment_list.h); no virtual calls, no allocation, no Lua.
#pragma once

#include "scene/scene.h"
#include "shading/pigments/pigment_context.h"

#include <cstdint>
#include <vector>

namespace lray {

/// Whether pigment `index` of `pigments` may read a hit's (u, v): a pattern
/// with a (u, v) map, or a checker with such a sub-pigment. The analytic
/// shapes leave (u, v) out of hits of other textures (Entity::readsUv).
bool pigmentReadsUv(const std::vector<Pigment> &pigments, uint32_t index);

} // namespace lray
