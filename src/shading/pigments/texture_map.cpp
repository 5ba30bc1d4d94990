// Pipeline: shading. Texture map formulas; see texture_map.h for the
// exact definitions of each map.
#include "shading/pigments/texture_map.h"

#include "math/constants.h"

#include <cmath>

namespace lray {

TexCoord2 mapPoint2D(const TextureMap &map, const Hit &hit) {
  const Vec3 &p = hit.pObject;
  switch (map.kind) {
  case TextureMap::Kind::TextureMap2D:
    return {hit.u, hit.v};
  case TextureMap::Kind::UVMap:
    return {hit.u * map.scaleS + map.translateS, hit.v * map.scaleT + map.translateT};
  case TextureMap::Kind::SphericalMap: {
    double r = length(p);
    double s = (std::atan2(p.z, p.x) + kPi) / (2 * kPi);
    double t = r > 0 ? (p.y / r + 1) / 2 : 0.5;
    return {s, t};
  }
  case TextureMap::Kind::CylindricalMap: {
    double a = std::atan2(p.z, p.x);
    if (a < 0) a += 2 * kPi;
    double s = a / (2 * kPi);
    return {s < 1 ? s : 0, p.y}; // a tiny negative angle may round up to a full turn
  }
  case TextureMap::Kind::TextureMap3D:
  case TextureMap::Kind::LinearMap: {
    Vec3 q = mapPoint3D(map, hit);
    return {q.x, q.y};
  }
  }
  return {hit.u, hit.v};
}

Vec3 mapPoint3D(const TextureMap &map, const Hit &hit) {
  switch (map.kind) {
  case TextureMap::Kind::TextureMap3D:
    return hit.pObject;
  case TextureMap::Kind::LinearMap:
    return map.transform.applyPoint(hit.pObject);
  case TextureMap::Kind::TextureMap2D:
  case TextureMap::Kind::UVMap:
  case TextureMap::Kind::SphericalMap:
  case TextureMap::Kind::CylindricalMap: {
    TexCoord2 st = mapPoint2D(map, hit);
    return {st.s, st.t, 0};
  }
  }
  return hit.pObject;
}

} // namespace lray
