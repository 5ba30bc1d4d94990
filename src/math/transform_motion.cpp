// Pipeline: shared math. Decomposing, interpolating and bounding moving
// transforms (transform_motion.h).
#include "math/transform_motion.h"

#include <algorithm>
#include <cmath>

namespace lray {

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 linearPart(const Mat4 &m) {
  Mat3 a{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      a[i][j] = m.m[i][j];
  return a;
}

double det(const Mat3 &a) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
         a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/// The inverse transpose of a (a invertible).
Mat3 inverseTranspose(const Mat3 &a) {
  const double id = 1 / det(a);
  Mat3 r{};
  r[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) * id;
  r[0][1] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) * id;
  r[0][2] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) * id;
  r[1][0] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * id;
  r[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * id;
  r[1][2] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * id;
  r[2][0] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * id;
  r[2][1] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * id;
  r[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * id;
  return r;
}

Mat3 product(const Mat3 &a, const Mat3 &b) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}

Mat3 transposed(const Mat3 &a) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i][j] = a[j][i];
  return r;
}

/// The rotation of a proper orthogonal matrix (Shepperd's method: the
/// largest of the four candidates, for accuracy).
Quaternion toQuaternion(const Mat3 &r) {
  const double trace = r[0][0] + r[1][1] + r[2][2];
  Quaternion q;
  if (trace > 0) {
    const double s = std::sqrt(trace + 1) * 2;
    q = {s / 4, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s};
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = std::sqrt(1 + r[0][0] - r[1][1] - r[2][2]) * 2;
    q = {(r[2][1] - r[1][2]) / s, s / 4, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s};
  } else if (r[1][1] > r[2][2]) {
    const double s = std::sqrt(1 + r[1][1] - r[0][0] - r[2][2]) * 2;
    q = {(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, s / 4, (r[1][2] + r[2][1]) / s};
  } else {
    const double s = std::sqrt(1 + r[2][2] - r[0][0] - r[1][1]) * 2;
    q = {(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, s / 4};
  }
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

Mat3 toMatrix(const Quaternion &q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

double dot(const Quaternion &a, const Quaternion &b) {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

/// The angle a rotates through to reach b the shorter way.
double turnAngle(const Quaternion &a, const Quaternion &b) {
  return 2 * std::acos(std::min(1.0, std::fabs(dot(a, b))));
}

TransformParts lerpParts(const TransformParts &a, const TransformParts &b, double u) {
  TransformParts r;
  r.translation = a.translation * (1 - u) + b.translation * u;
  r.rotation = slerp(a.rotation, b.rotation, u);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.stretch[i][j] = a.stretch[i][j] * (1 - u) + b.stretch[i][j] * u;
  return r;
}

} // namespace

TransformParts decompose(const Mat4 &m) {
  TransformParts parts;
  parts.translation = {m.m[0][3], m.m[1][3], m.m[2][3]};
  const Mat3 a = linearPart(m);
  // Polar decomposition by Higham's iteration R <- (R + R^-T) / 2, which
  // converges quadratically to the orthogonal factor of an invertible a.
  Mat3 r = a;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Mat3 it = inverseTranspose(r);
    double change = 0;
    Mat3 next{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        next[i][j] = (r[i][j] + it[i][j]) / 2;
        change = std::max(change, std::fabs(next[i][j] - r[i][j]));
      }
    r = next;
    if (change <= 1e-15) break;
  }
  // A mirroring a gives an improper r: -r is a rotation and -s the stretch.
  if (det(r) < 0)
    for (auto &row : r)
      for (double &v : row)
        v = -v;
  parts.rotation = toQuaternion(r);
  parts.stretch = product(transposed(toMatrix(parts.rotation)), a);
  return parts;
}

Mat4 compose(const TransformParts &parts) {
  const Mat3 l = product(toMatrix(parts.rotation), parts.stretch);
  Mat4 m = Mat4::identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.m[i][j] = l[i][j];
  m.m[0][3] = parts.translation.x;
  m.m[1][3] = parts.translation.y;
  m.m[2][3] = parts.translation.z;
  return m;
}

Quaternion slerp(const Quaternion &a, const Quaternion &b0, double u) {
  Quaternion b = b0;
  double c = dot(a, b);
  if (c < 0) {
    b = {-b.w, -b.x, -b.y, -b.z};
    c = -c;
  }
  double wa, wb;
  if (c > 0.9999) { // nearly the same: linear, renormalised below
    wa = 1 - u;
    wb = u;
  } else {
    const double theta = std::acos(c);
    const double s = std::sin(theta);
    wa = std::sin((1 - u) * theta) / s;
    wb = std::sin(u * theta) / s;
  }
  Quaternion q{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
  const double n = std::sqrt(dot(q, q));
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

TransformMotion::TransformMotion(std::vector<Transform> steps) : steps_(std::move(steps)) {
  parts_.reserve(steps_.size());
  for (const Transform &t : steps_)
    parts_.push_back(decompose(t.matrix()));
}

void TransformMotion::locate(double time, size_t &i, double &u) const {
  const size_t segments = steps_.size() - 1;
  const double x = std::clamp(time, 0.0, 1.0) * static_cast<double>(segments);
  i = std::min(static_cast<size_t>(x), segments - 1);
  u = x - static_cast<double>(i);
}

Transform TransformMotion::at(double time) const {
  size_t i;
  double u;
  locate(time, i, u);
  if (u == 0) return steps_[i];
  if (u == 1) return steps_[i + 1];
  return Transform::fromMatrix(compose(lerpParts(parts_[i], parts_[i + 1], u)));
}

Mat4 TransformMotion::matrixAt(double time) const {
  size_t i;
  double u;
  locate(time, i, u);
  if (u == 0) return steps_[i].matrix();
  if (u == 1) return steps_[i + 1].matrix();
  return compose(lerpParts(parts_[i], parts_[i + 1], u));
}

// A point x of the object moves as p(u) = T(u) + R(u) S(u) x over segment
// i (u in [0, 1]). Its speed |p'| is at most |T1 - T0| + theta |S(u) x| +
// |(S1 - S0) x|, where theta is the segment's turn (slerp turns at a
// constant rate). |S(u) x| is convex in u and in x (the norm of a linear
// function), so over the box and the segment it is largest at a corner at
// an end; |(S1 - S0) x| at a corner. Samples 1/n apart then leave every
// point within half the distance it covers in 1/n of the segment.
double TransformMotion::segmentSpeed(size_t i, const Bounds3 &box) const {
  const TransformParts &a = parts_[i], &b = parts_[i + 1];
  double stretched = 0, stretching = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 x(c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y,
                 c & 4 ? box.hi.z : box.lo.z);
    auto apply = [&x](const Mat3 &s, const Mat3 *minus) {
      Vec3 r;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          r[k] += (s[k][j] - (minus ? (*minus)[k][j] : 0)) * x[j];
      return length(r);
    };
    stretched = std::max({stretched, apply(a.stretch, nullptr), apply(b.stretch, nullptr)});
    stretching = std::max(stretching, apply(b.stretch, &a.stretch));
  }
  return length(b.translation - a.translation) + turnAngle(a.rotation, b.rotation) * stretched +
         stretching;
}

Bounds3 TransformMotion::sweptBounds(const Bounds3 &objectBox, double t0, double t1) const {
  return sweptBounds(objectBox, t0, t1, [&](const Transform &xf) {
    Bounds3 world;
    for (int c = 0; c < 8; ++c)
      world.extend(xf.applyPoint({c & 1 ? objectBox.hi.x : objectBox.lo.x,
                                  c & 2 ? objectBox.hi.y : objectBox.lo.y,
                                  c & 4 ? objectBox.hi.z : objectBox.lo.z}));
    const Vec3 pad = (abs(world.lo) + abs(world.hi)) * 1e-14; // the products' rounding
    return Bounds3(world.lo - pad, world.hi + pad);
  });
}

} // namespace lray
