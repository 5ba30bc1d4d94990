// Pipeline: shared math. 3-component double vector used for points,
// directions and normals in every space (the name of the variable says which).
#pragma once

#include <algorithm>
#include <cmath>

namespace lray {

/// A 3-D vector of doubles (points, directions, normals).
struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double &operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3 operator+(const Vec3 &o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3 &o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  Vec3 &operator+=(const Vec3 &o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3 &operator-=(const Vec3 &o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Vec3 &operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3 &o) const { return x == o.x && y == o.y && z == o.z; }
  constexpr bool operator!=(const Vec3 &o) const { return !(*this == o); }
};

constexpr Vec3 operator*(double s, const Vec3 &v) { return v * s; }
constexpr double dot(const Vec3 &a, const Vec3 &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3 &a, const Vec3 &b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3 &v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3 &v) { return v / length(v); }
/// v scaled to unit length (one division; normalize divides three times).
inline Vec3 unitVector(const Vec3 &v) { return v * (1 / length(v)); }
inline Vec3 abs(const Vec3 &v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }
inline Vec3 min(const Vec3 &a, const Vec3 &b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 max(const Vec3 &a, const Vec3 &b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline double maxComponent(const Vec3 &v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool isFinite(const Vec3 &v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Single-precision 3-vector, used only for compact mesh storage shared with Embree.
struct Vec3f {
  float x = 0, y = 0, z = 0;
};

inline Vec3 toVec3(const Vec3f &v) { return {v.x, v.y, v.z}; }
inline Vec3f toVec3f(const Vec3 &v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

/// 2-D texture coordinate, compact storage for meshes.
struct Vec2f {
  float u = 0, v = 0;
};

} // namespace lray
