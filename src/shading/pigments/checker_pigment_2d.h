// Pipeline: shading. CheckerPigment2D (lua/README.md, "Textures, finishes and pigments"): two
// sub-pigments in a checkerboard of the map's (s, t): pigment1 where (frac(s) > 0.5) == (frac(t) >
// 0.5), frac(x) = x - floor(x).
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct CheckerPigment2D {
  static constexpr const char *kName = "CheckerPigment2D";
  static constexpr int kDimensions = 2;

  uint32_t pigment1 = 0, pigment2 = 0; ///< indices into Scene::pigments

  /// Whether pigment1 applies at (s, t).
  static bool picksFirst(double s, double t);
  Color evaluate(const PigmentContext &c) const;
};

} // namespace lray
