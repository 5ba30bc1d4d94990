// Pipeline: shared math. Linear RGB colour, unclamped until the film writes it.
#pragma once

#include <cmath>

namespace lray {

/// An RGB colour; components are unbounded until an LDR image is written.
struct Color {
  double r = 0, g = 0, b = 0;

  constexpr Color() = default;
  constexpr Color(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}

  constexpr Color operator+(const Color &o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Color operator-(const Color &o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Color operator*(const Color &o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Color operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Color operator/(double s) const { return {r / s, g / s, b / s}; }
  Color &operator+=(const Color &o) { r += o.r; g += o.g; b += o.b; return *this; }
  Color &operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
  constexpr bool operator==(const Color &o) const { return r == o.r && g == o.g && b == o.b; }
  constexpr bool operator!=(const Color &o) const { return !(*this == o); }
  constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  constexpr double maxComponent() const { return r > g ? (r > b ? r : b) : (g > b ? g : b); }
};

constexpr Color operator*(double s, const Color &c) { return c * s; }

inline bool isFinite(const Color &c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

} // namespace lray
