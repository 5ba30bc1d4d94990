// Pipeline: shared math. Affine transform construction, composition, inversion.
#include "math/transform.h"

#include "math/constants.h"

#include <cmath>
#include <sstream>

namespace lray {

namespace {

// Inverse of an affine matrix; returns false when the linear part is singular
// relative to the size of its entries.
bool invertAffine(const Mat4 &a, Mat4 &out) {
  const auto &m = a.m;
  double det = a.det3();
  double scale = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) scale = std::max(scale, std::fabs(m[i][j]));
  if (!std::isfinite(det) || scale == 0 || std::fabs(det) <= 1e-300 ||
      std::fabs(det) <= scale * scale * scale * 1e-14)
    return false;
  double id = 1.0 / det;
  Mat4 r = Mat4::identity();
  r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
  r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
  r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
  r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
  r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
  r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
  r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
  r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
  r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
  for (int i = 0; i < 3; ++i)
    r.m[i][3] = -(r.m[i][0] * m[0][3] + r.m[i][1] * m[1][3] + r.m[i][2] * m[2][3]);
  out = r;
  return true;
}

} // namespace

Mat4 Mat4::identity() {
  Mat4 r;
  for (int i = 0; i < 4; ++i) r.m[i][i] = 1;
  return r;
}

Mat4 Mat4::operator*(const Mat4 &o) const {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

double Mat4::det3() const {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Transform &Transform::cacheDerived() {
  identity_ = m_ == Mat4::identity();
  norms_ = {0, 0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    double row = 0, invRow = 0;
    for (int j = 0; j < 3; ++j) {
      row += std::fabs(m_.m[i][j]);
      invRow += std::fabs(inv_.m[i][j]);
    }
    norms_[0] = std::max(norms_[0], row);
    norms_[1] = std::max(norms_[1], invRow);
    norms_[2] = std::max(norms_[2], std::fabs(m_.m[i][3]));
    norms_[3] = std::max(norms_[3], std::fabs(inv_.m[i][3]));
  }
  return *this;
}

Transform Transform::fromMatrix(const Mat4 &m) {
  Transform t;
  t.m_ = m;
  if (!invertAffine(m, t.inv_)) {
    t.singular_ = true;
    t.inv_ = Mat4::identity();
  }
  return t.cacheDerived();
}

Transform Transform::fromMatrixAndInverse(const Mat4 &m, const Mat4 &inverse) {
  Transform t;
  t.m_ = m;
  t.inv_ = inverse;
  return t.cacheDerived();
}

Transform Transform::translate(const Vec3 &v) {
  Mat4 m = Mat4::identity();
  m.m[0][3] = v.x;
  m.m[1][3] = v.y;
  m.m[2][3] = v.z;
  Transform t;
  t.m_ = m;
  t.inv_ = Mat4::identity();
  t.inv_.m[0][3] = -v.x;
  t.inv_.m[1][3] = -v.y;
  t.inv_.m[2][3] = -v.z;
  t.singular_ = !isFinite(v);
  return t.cacheDerived();
}

Transform Transform::scale(double sx, double sy, double sz) {
  Mat4 m = Mat4::identity();
  m.m[0][0] = sx;
  m.m[1][1] = sy;
  m.m[2][2] = sz;
  return fromMatrix(m);
}

Transform Transform::rotate(const Vec3 &axis, double degrees) {
  double len = length(axis);
  if (!(len > 0) || !std::isfinite(len) || !std::isfinite(degrees)) {
    Transform t;
    t.singular_ = true;
    return t;
  }
  Vec3 a = axis / len;
  // Exact values for multiples of 90 degrees keep axis-aligned scenes exact.
  double rad = degrees * kPi / 180.0;
  double s = std::sin(rad), c = std::cos(rad);
  double q = std::fmod(degrees, 90.0);
  if (q == 0) {
    long k = static_cast<long>(std::fmod(degrees / 90.0, 4.0));
    if (k < 0) k += 4;
    static const double sins[4] = {0, 1, 0, -1};
    static const double coss[4] = {1, 0, -1, 0};
    s = sins[k];
    c = coss[k];
  }
  Mat4 m = Mat4::identity();
  m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
  m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
  m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
  m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
  m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
  m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
  m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
  m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
  m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
  Transform t;
  t.m_ = m;
  // A rotation's inverse is its transpose.
  t.inv_ = Mat4::identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.inv_.m[i][j] = m.m[j][i];
  return t.cacheDerived();
}

Transform Transform::lookAt(const Vec3 &pos, const Vec3 &at, const Vec3 &up) {
  Vec3 dir = at - pos;
  double dl = length(dir);
  Vec3 xAxis = cross(up, dir);
  double xl = length(xAxis);
  if (!(dl > 0) || !(xl > 1e-12 * dl * length(up)) || !isFinite(pos) || !std::isfinite(xl)) {
    Transform t;
    t.singular_ = true;
    return t;
  }
  Vec3 zAxis = dir / dl;
  xAxis = xAxis / xl;
  Vec3 yAxis = cross(zAxis, xAxis);
  Mat4 m = Mat4::identity();
  for (int i = 0; i < 3; ++i) {
    m.m[i][0] = xAxis[i];
    m.m[i][1] = yAxis[i];
    m.m[i][2] = zAxis[i];
    m.m[i][3] = pos[i];
  }
  return fromMatrix(m);
}

Transform Transform::operator*(const Transform &o) const {
  Transform t;
  t.m_ = m_ * o.m_;
  t.inv_ = o.inv_ * inv_;
  t.singular_ = singular_ || o.singular_;
  return t.cacheDerived();
}

Transform Transform::inverse() const {
  Transform t;
  t.m_ = inv_;
  t.inv_ = m_;
  t.singular_ = singular_;
  return t.cacheDerived();
}

double Transform::maxLinearEntry() const {
  double s = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s = std::max(s, std::fabs(m_.m[i][j]));
  return s;
}

std::string Transform::toString() const {
  std::ostringstream os;
  os << "Transform(";
  for (int i = 0; i < 3; ++i) {
    os << (i ? ", " : "") << "[";
    for (int j = 0; j < 4; ++j) os << (j ? " " : "") << m_.m[i][j];
    os << "]";
  }
  os << ")";
  return os.str();
}

} // namespace lray
