// Pipeline: shading. The blend marble and wood share: a * color1 +
// (1 - a) * color2 with a = |sin(t)| (0 where not finite).
#pragma once

#include "math/color.h"

#include <cmath>

namespace lray {

inline Color sineBlend(const Color &color1, const Color &color2, double t) {
  double a = std::fabs(std::sin(t));
  if (!std::isfinite(a)) a = 0;
  return color1 * a + color2 * (1 - a);
}

} // namespace lray
