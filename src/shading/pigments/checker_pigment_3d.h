// Pipeline: shading. CheckerPigment3D (lua/README.md, "Textures, finishes and pigments"): two
// sub-pigments in unit cubes of the map's 3-D point: pigment1 where floor(x) + floor(y) + floor(z)
// is even.
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct CheckerPigment3D {
  static constexpr const char *kName = "CheckerPigment3D";
  static constexpr int kDimensions = 3;

  uint32_t pigment1 = 0, pigment2 = 0; ///< indices into Scene::pigments

  /// Whether pigment1 applies at p.
  static bool picksFirst(const Vec3 &p);
  Color evaluate(const PigmentContext &c) const;
};

} // namespace lray
