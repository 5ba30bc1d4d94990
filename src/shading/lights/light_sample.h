// Pipeline: shading. What every light kind gives the integrator for one of
// its samples as seen from a shading point: where the shadow ray goes and
// the light it brings if nothing blocks it.
#pragma once

#include "math/color.h"
#include "math/vec3.h"

namespace lray {

struct LightSample {
  Vec3 target; ///< world point the shadow ray is aimed at (on the light)
  Color color; ///< light arriving from it, already weighted (black: adds nothing)
};

} // namespace lray
