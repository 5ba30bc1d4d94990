// Pipeline: shading. See checker_pigment_3d.h.
#include "shading/pigments/checker_pigment_3d.h"

#include "shading/pigments/texture_map.h"

#include <cmath>

namespace lray {

bool CheckerPigment3D::picksFirst(const Vec3 &p) {
  double sum = std::floor(p.x) + std::floor(p.y) + std::floor(p.z);
  // Parity that also holds for negative sums (fmod keeps the sign).
  return sum - 2 * std::floor(sum / 2) == 0;
}

Color CheckerPigment3D::evaluate(const PigmentContext &c) const {
  return pigment_detail::evaluateNested(c, picksFirst(mapPoint3D(c.map, c.hit)) ? pigment1
                                                                                : pigment2);
}

} // namespace lray
