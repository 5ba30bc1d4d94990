// Pipeline: scene description. A texture map's parameters (SPEC 7): how a
// pigment's lookup point is made from a hit (shading/texture_map.h has the
// formulas).
#pragma once

#include "math/transform.h"
#include "scene/scene_error.h"

#include <cstdint>

namespace lray {

/// How a pigment's lookup point is made from a hit (SPEC 7 texture maps).
struct TextureMap {
  enum class Kind : uint8_t {
    TextureMap2D,   ///< (s,t) = (u,v)
    UVMap,          ///< s = u*scaleS + translateS, t likewise
    SphericalMap,   ///< 2-D from the local point by angles (ext)
    CylindricalMap, ///< 2-D from the local point by angle and height (ext)
    TextureMap3D,   ///< the entity-local point
    LinearMap,      ///< the entity-local point with `transform` applied
  };
  Kind kind = Kind::TextureMap2D;
  double scaleS = 1, scaleT = 1, translateS = 0, translateT = 0;
  Transform transform;
  SourceLocation loc; ///< where the map was made (none for a default map)

  bool is3D() const { return kind == Kind::TextureMap3D || kind == Kind::LinearMap; }
};

} // namespace lray
