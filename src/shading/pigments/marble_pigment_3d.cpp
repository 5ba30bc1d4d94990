// Pipeline: shading. See marble_pigment_3d.h.
#include "shading/pigments/marble_pigment_3d.h"

#include "shading/pigments/perlin_noise.h"
#include "shading/pigments/sine_blend.h"
#include "shading/pigments/texture_map.h"

#include <cmath>

namespace lray {

Color MarblePigment3D::at(const Vec3 &p) const {
  return sineBlend(color1, color2, dot(p, frequency) + power * turbulence(p, size));
}

Color MarblePigment3D::evaluate(const PigmentContext &c) const {
  return at(mapPoint3D(c.map, c.hit));
}

} // namespace lray
