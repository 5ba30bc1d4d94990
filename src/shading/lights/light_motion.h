// Pipeline: shading. A light that moves while the shutter is open
// (lua/README.md, "Motion blur"): its position at each motion step less
// its position at step 0, interpolated linearly between the steps. The
// light keeps the orientation and size it has at step 0.
#pragma once

#include "math/motion_steps.h"
#include "math/vec3.h"

#include <vector>

namespace lray {

struct LightMotion {
  std::vector<Vec3> offsets; ///< one per motion step, offsets[0] = 0

  /// The offset at shutter time `time` in [0, 1] (clamped).
  Vec3 at(double time) const {
    size_t i;
    double u;
    locateMotionStep(time, offsets.size(), i, u);
    return offsets[i] * (1 - u) + offsets[i + 1] * u;
  }
};

} // namespace lray
