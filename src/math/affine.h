// Pipeline: geometry (internal). Small vector helpers for the per-ray paths;
// the affine products (affinePoint, affineVector, affineNormal) are in
// math/transform.h, inline beside Transform's own.
#pragma once

#include "math/transform.h"
#include "math/vec3.h"

namespace lray {

/// v scaled to unit length (one division).
inline Vec3 unitVector(const Vec3 &v) { return v * (1 / length(v)); }

} // namespace lray
