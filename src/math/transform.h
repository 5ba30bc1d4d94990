// Pipeline: shared math. Affine transforms (double precision) with their
// inverses; named destination-from-source where stored (worldFromObject).
#pragma once

#include "math/ray.h"
#include "math/vec3.h"

#include <array>
#include <string>

namespace lray {

/// A row-major 4x4 matrix; affine transforms use only the top three rows.
struct Mat4 {
  std::array<std::array<double, 4>, 4> m{};

  static Mat4 identity();
  Mat4 operator*(const Mat4 &o) const;
  /// Determinant of the upper-left 3x3 block (the linear part).
  double det3() const;
  bool operator==(const Mat4 &o) const { return m == o.m; }
};

/// m * (p, 1).
inline Vec3 affinePoint(const Mat4 &mat, const Vec3 &p) {
  const auto &m = mat.m;
  return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
          m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
          m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}

/// m * (v, 0).
inline Vec3 affineVector(const Mat4 &mat, const Vec3 &v) {
  const auto &m = mat.m;
  return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
          m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
          m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

/// A normal through `inv` = the inverse of the point transform: inv^T n.
inline Vec3 affineNormal(const Mat4 &inv, const Vec3 &n) {
  const auto &m = inv.m;
  return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
          m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
          m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
}

/// An invertible affine transform. Construction never yields NaN: the
/// factories below report a singular matrix through `singular()`, and the
/// scene layer turns that into a SceneError at the script line.
class Transform {
public:
  Transform() = default; // identity

  static Transform identity() { return {}; }
  static Transform translate(const Vec3 &v);
  static Transform scale(double sx, double sy, double sz);
  /// Rotation by `degrees` about `axis` (normalised first); right-hand rule
  /// in the math sense: rotate(z, 90) takes +x to +y, rotate(y, 90) takes +x to -z.
  /// A zero axis gives a singular transform.
  static Transform rotate(const Vec3 &axis, double degrees);
  /// Moves the origin to `pos` with +z pointing at `at` and +y towards `up`.
  /// `up` parallel to at - pos (or at == pos) gives a singular transform.
  static Transform lookAt(const Vec3 &pos, const Vec3 &at, const Vec3 &up);
  /// From a matrix; marks the result singular if its linear part is not invertible.
  static Transform fromMatrix(const Mat4 &m);
  /// From a matrix and its inverse, computed together by the caller (a
  /// moving transform's, math/transform_motion.h); not checked.
  static Transform fromMatrixAndInverse(const Mat4 &m, const Mat4 &inverse);

  /// `a * b` applies b first, then a.
  Transform operator*(const Transform &o) const;
  Transform inverse() const;

  // Inline (the same products as affinePoint and the others): camera rays
  // and lights place a point or vector per sample.
  Vec3 applyPoint(const Vec3 &p) const { return affinePoint(m_, p); }
  Vec3 applyVector(const Vec3 &v) const { return affineVector(m_, v); }
  /// Transforms a normal by the inverse transpose (result not normalised).
  Vec3 applyNormal(const Vec3 &n) const { return affineNormal(inv_, n); }
  Ray applyRay(const Ray &r) const {
    return {applyPoint(r.o), applyVector(r.d), r.tMin, r.tMax, r.time};
  }

  const Mat4 &matrix() const { return m_; }
  const Mat4 &inverseMatrix() const { return inv_; }
  bool singular() const { return singular_; }
  /// Exactly the identity matrix (a fast path for the per-hit code).
  bool isIdentity() const { return identity_; }
  /// Infinity norm (largest absolute row sum) of the linear part of the
  /// matrix, of the inverse's, and the largest absolute translation component
  /// of each: the constants of math/error_bound.h's rule, computed once
  /// here instead of on every hit.
  double linearNorm() const { return norms_[0]; }
  double inverseLinearNorm() const { return norms_[1]; }
  double translationNorm() const { return norms_[2]; }
  double inverseTranslationNorm() const { return norms_[3]; }
  /// Largest absolute entry of the linear part (used for error bounds).
  double maxLinearEntry() const;
  /// Human-readable matrix rows, for messages and Lua tostring.
  std::string toString() const;

private:
  /// Recomputes identity_ and norms_ from m_ and inv_; every factory that
  /// sets them ends with it.
  Transform &cacheDerived();

  Mat4 m_ = Mat4::identity();
  Mat4 inv_ = Mat4::identity();
  std::array<double, 4> norms_{1, 1, 0, 0};
  bool singular_ = false;
  bool identity_ = true;
};

} // namespace lray
