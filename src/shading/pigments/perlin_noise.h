// Pipeline: shading. Ken Perlin's improved gradient noise ("Improving
// Noise", SIGGRAPH 2002) and the turbulence sum built on it; used by the
// marble and wood pigments. Pure functions of the point: no state, no
// allocation, safe from any thread.
#pragma once

#include "math/vec3.h"

namespace lray {

/// Improved gradient noise at point p (pigment space, lattice spacing 1).
/// Zero at every integer lattice point, C2-continuous, within [-1, 1].
/// Non-finite input gives 0.
double perlinNoise(const Vec3 &p);

/// turb(p, size) = sum over octaves k = 0, 1, ... while 2^-k >= size of
/// |noise(p * 2^k)| / 2^k (lua/README.md, "Textures, finishes and pigments"). At most 32 octaves,
/// so a size <= 0 cannot loop forever.
double turbulence(const Vec3 &p, double size);

} // namespace lray
