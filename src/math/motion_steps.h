// Pipeline: shared math. Where a time of the open shutter falls among a
// motion's k evenly spaced steps (lua/README.md, "Motion blur"): shared by
// moving transforms, meshes and lights.
#pragma once

#include <algorithm>
#include <cstddef>

namespace lray {

/// `time` in [0, 1] (clamped) over `steps` >= 2 motion steps: segment i
/// (steps i and i + 1) and the fraction u of it.
inline void locateMotionStep(double time, size_t steps, size_t &i, double &u) {
  const size_t segments = steps - 1;
  const double x = std::clamp(time, 0.0, 1.0) * static_cast<double>(segments);
  i = std::min(static_cast<size_t>(x), segments - 1);
  u = x - static_cast<double>(i);
}

} // namespace lray
