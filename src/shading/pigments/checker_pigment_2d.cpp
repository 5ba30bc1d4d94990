// Pipeline: shading. See checker_pigment_2d.h.
#include "shading/pigments/checker_pigment_2d.h"

#include "shading/pigments/texture_map.h"

#include <cmath>

namespace lray {

bool CheckerPigment2D::picksFirst(double s, double t) {
  double fs = s - std::floor(s);
  double ft = t - std::floor(t);
  return (fs > 0.5) == (ft > 0.5);
}

Color CheckerPigment2D::evaluate(const PigmentContext &c) const {
  TexCoord2 st = mapPoint2D(c.map, c.hit);
  return pigment_detail::evaluateNested(c, picksFirst(st.s, st.t) ? pigment1 : pigment2);
}

} // namespace lray
