// Pipeline: shared math. A 64-bit mixing function for counter-based random
// numbers and scramble seeds (math/random.h, math/owen_sobol.h).
#pragma once

#include <cstdint>

namespace lray {

/// SplitMix64's finaliser (Steele et al. 2014).
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

} // namespace lray
