// Pipeline: shading (a pigment's vocabulary). Texture maps (lua/README.md): a
// map's parameters, and how they turn a hit record into the point a
// pigment is looked up at, either 2-D (s, t) or 3-D.
#pragma once

#include "math/hit.h"
#include "math/transform.h"
#include "util/scene_error.h"

#include <cstdint>

namespace lray {

/// How a pigment's lookup point is made from a hit (lua/README.md, "Texture maps").
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
  /// Whether the map reads the hit's (u, v): the others read its object-space point alone.
  bool readsUv() const { return kind == Kind::TextureMap2D || kind == Kind::UVMap; }
};

/// A 2-D pigment lookup coordinate (unitless; a texture repeats every 1).
struct TexCoord2 {
  double s = 0, t = 0;
};

/// (s, t) for a 2-D pigment:
/// - TextureMap2D: (u, v) of the hit.
/// - UVMap: s = u * scaleS + translateS, t = v * scaleT + translateT.
/// - SphericalMap (ext), from the entity-local point p = Hit::pObject, the
///   unit sphere's own uv (lua/README.md, "Entities") extended to any point by its direction:
///   s = (atan2(p.z, p.x) + pi) / (2 pi), t = (p.y / |p| + 1) / 2 (t = 0.5 at p = 0).
/// - CylindricalMap (ext), the cylinder's side uv (lua/README.md, "Entities") about the local
///   y axis: s = a / (2 pi) with a = atan2(p.z, p.x) taken in [0, 2 pi)
///   (from +x towards +z, as geometry's turnFraction), t = p.y.
/// A 3-D map given to a 2-D pigment uses (x, y) of its 3-D point.
TexCoord2 mapPoint2D(const TextureMap &map, const Hit &hit);

/// The 3-D point for a 3-D pigment:
/// - TextureMap3D: the entity-local (object space) hit point.
/// - LinearMap: map.transform applied to that point.
/// A 2-D map given to a 3-D pigment uses (s, t, 0).
Vec3 mapPoint3D(const TextureMap &map, const Hit &hit);

} // namespace lray
