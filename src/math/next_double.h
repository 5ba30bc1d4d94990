// Pipeline: shared math. The neighbouring doubles of a value, as
// std::nextafter(x, +-infinity) gives them, without its library call: a
// spawned ray's origin is rounded away from its surface in each of its
// three coordinates (math/spawn.h), once per shadow ray.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace lray {

/// std::nextafter(x, +infinity): the least double greater than x (x itself
/// for +infinity and NaN).
inline double nextUp(double x) {
  if (!(x < std::numeric_limits<double>::infinity())) return x; // +inf, NaN
  if (x == 0) return std::numeric_limits<double>::denorm_min(); // from +0 and -0
  const uint64_t bits = std::bit_cast<uint64_t>(x);
  return std::bit_cast<double>(x > 0 ? bits + 1 : bits - 1);
}

/// std::nextafter(x, -infinity): the greatest double less than x.
inline double nextDown(double x) { return -nextUp(-x); }

} // namespace lray
