// Pipeline: script -> scene description. Attribute validators: each returns
// what was expected when the value is rejected, else null.
#pragma once

#include "math/color.h"

#include <string>

namespace lray::lua {

inline const char *nonNegativeColor(const Color &c) {
  return c.r >= 0 && c.g >= 0 && c.b >= 0 ? nullptr : "a colour with components >= 0";
}
inline const char *integratorName(const std::string &v) {
  return v == "whitted" || v == "path" ? nullptr : "\"whitted\" or \"path\"";
}
inline const char *positiveInteger(const int &v) { return v > 0 ? nullptr : "a positive integer"; }
inline const char *positiveNumber(const double &v) { return v > 0 ? nullptr : "a positive number"; }
inline const char *nonNegativeNumber(const double &v) {
  return v >= 0 ? nullptr : "a number >= 0";
}
inline const char *unitInterval(const double &v) {
  return v >= 0 && v <= 1 ? nullptr : "a number between 0 and 1";
}
/// The most motion steps (lua/README.md, "Motion blur"): scene(clock) runs
/// this many times a frame at most.
inline constexpr int kMaxMotionSteps = 16;
inline const char *motionStepCount(const int &v) {
  return v >= 2 && v <= kMaxMotionSteps ? nullptr : "an integer from 2 to 16";
}
inline const char *rightAngleOrLess(const double &v) {
  return v >= 0 && v <= 90 ? nullptr : "an angle between 0 and 90 degrees";
}
inline const char *fieldOfView(const double &v) {
  return v > 0 && v < 180 ? nullptr : "an angle between 0 and 180 degrees";
}

} // namespace lray::lua
