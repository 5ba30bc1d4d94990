// Pipeline: shading. See wood_pigment_3d.h.
#include "shading/pigments/wood_pigment_3d.h"

#include "shading/pigments/perlin_noise.h"
#include "shading/pigments/sine_blend.h"
#include "shading/pigments/texture_map.h"

#include <algorithm>
#include <cmath>

namespace lray {

Color WoodPigment3D::at(const Vec3 &p) const {
  double r2 = frequency.x * p.x * p.x + frequency.y * p.y * p.y;
  return sineBlend(color1, color2, std::sqrt(std::max(0.0, r2)) + power * turbulence(p, size));
}

Color WoodPigment3D::evaluate(const PigmentContext &c) const {
  return at(mapPoint3D(c.map, c.hit));
}

} // namespace lray
