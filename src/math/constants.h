// Pipeline: math. The constants every stage shares.
#pragma once

#include <numbers>

namespace lray {

inline constexpr double kPi = std::numbers::pi;
/// Radians per degree (scripts give angles in degrees).
inline constexpr double kDegree = kPi / 180;

} // namespace lray
