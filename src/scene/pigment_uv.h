// Pipeline: scene description. Which pigments read a hit's (u, v): the
// converter marks the entities whose texture does not (Entity::readsUv),
// and the analytic shapes leave (u, v) out of their hits.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace lray {

/// Whether pigment `index` of `pigments` may read a hit's (u, v): a pattern
/// with a (u, v) map (TextureMap::readsUv), or a checker with such a
/// sub-pigment.
bool pigmentReadsUv(const std::vector<Pigment> &pigments, uint32_t index);

} // namespace lray
