// Pipeline: math. Four rays' fields transposed into the lanes of
// math/lanes.h, one field of the four in each, for code that treats a few
// rays at once with the scalar code's operations lane by lane (Embree's
// 8-wide rays, SphereBound's line test).
#pragma once

#include "math/lanes.h"
#include "math/ray.h"

#include <cstddef>
#include <cstring>

namespace lray::lanes {

struct RayLanes {
  Lanes ox, oy, oz, dx, dy, dz, tMin, tMax;
};

static_assert(offsetof(Ray, o) == 0 && offsetof(Ray, d) == 24 && offsetof(Ray, tMin) == 48 &&
              offsetof(Ray, tMax) == 56);

/// The fields of *rays[0..3].
[[gnu::always_inline]] inline void loadRays(const Ray *const (&rays)[4], RayLanes &out) {
  // (o.x, o.y, o.z, d.x) and (d.y, d.z, tMin, tMax) of each ray, loaded
  // whole (copies through an array went by the stack).
  Lanes a0, a1, a2, a3, b0, b1, b2, b3;
  std::memcpy(&a0, &rays[0]->o.x, sizeof(Lanes));
  std::memcpy(&a1, &rays[1]->o.x, sizeof(Lanes));
  std::memcpy(&a2, &rays[2]->o.x, sizeof(Lanes));
  std::memcpy(&a3, &rays[3]->o.x, sizeof(Lanes));
  std::memcpy(&b0, &rays[0]->d.y, sizeof(Lanes));
  std::memcpy(&b1, &rays[1]->d.y, sizeof(Lanes));
  std::memcpy(&b2, &rays[2]->d.y, sizeof(Lanes));
  std::memcpy(&b3, &rays[3]->d.y, sizeof(Lanes));
  const Lanes a01e = __builtin_shuffle(a0, a1, Mask{0, 4, 2, 6});
  const Lanes a01o = __builtin_shuffle(a0, a1, Mask{1, 5, 3, 7});
  const Lanes a23e = __builtin_shuffle(a2, a3, Mask{0, 4, 2, 6});
  const Lanes a23o = __builtin_shuffle(a2, a3, Mask{1, 5, 3, 7});
  const Lanes b01e = __builtin_shuffle(b0, b1, Mask{0, 4, 2, 6});
  const Lanes b01o = __builtin_shuffle(b0, b1, Mask{1, 5, 3, 7});
  const Lanes b23e = __builtin_shuffle(b2, b3, Mask{0, 4, 2, 6});
  const Lanes b23o = __builtin_shuffle(b2, b3, Mask{1, 5, 3, 7});
  out.ox = __builtin_shuffle(a01e, a23e, Mask{0, 1, 4, 5});
  out.oz = __builtin_shuffle(a01e, a23e, Mask{2, 3, 6, 7});
  out.oy = __builtin_shuffle(a01o, a23o, Mask{0, 1, 4, 5});
  out.dx = __builtin_shuffle(a01o, a23o, Mask{2, 3, 6, 7});
  out.dy = __builtin_shuffle(b01e, b23e, Mask{0, 1, 4, 5});
  out.tMin = __builtin_shuffle(b01e, b23e, Mask{2, 3, 6, 7});
  out.dz = __builtin_shuffle(b01o, b23o, Mask{0, 1, 4, 5});
  out.tMax = __builtin_shuffle(b01o, b23o, Mask{2, 3, 6, 7});
}

} // namespace lray::lanes
