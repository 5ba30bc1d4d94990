// Pipeline: shading. WoodPigment3D (lua/README.md, "Textures, finishes and pigments"): rings about
// z, t = sqrt(fx * p.x^2 + fy * p.y^2) + power * turb(p, size), colour as marble's blend (a
// negative radicand counts as 0).
#pragma once

#include "shading/pigments/pigment_context.h"

namespace lray {

struct WoodPigment3D {
  static constexpr const char *kName = "WoodPigment3D";
  static constexpr int kDimensions = 3;

  Color color1{0, 0, 0}, color2{1, 1, 1};
  Vec3 frequency{1024, 1024, 1024};
  double power = 2;
  double size = 0.2;

  Color evaluate(const PigmentContext &c) const;
  /// The formula at a point of pigment space.
  Color at(const Vec3 &p) const;
};

} // namespace lray
