// Pipeline: shading. MarblePigment3D (lua/README.md, "Textures, finishes and pigments"): bands
// across `frequency`, a = |sin(dot(p, frequency) + power * turb(p, size))|, colour a * color1 + (1
// - a) * color2 (p the map's 3-D point).
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct MarblePigment3D {
  static constexpr const char *kName = "MarblePigment3D";
  static constexpr int kDimensions = 3;

  Color color1{0, 0, 0}, color2{1, 1, 1};
  Vec3 frequency{5, 5, 5};
  double power = 2;
  double size = 0.2;

  Color evaluate(const PigmentContext &c) const;
  /// The formula at a point of pigment space.
  Color at(const Vec3 &p) const;
};

} // namespace lray
