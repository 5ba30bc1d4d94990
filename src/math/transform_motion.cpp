// Pipeline: shared math. Decomposing, interpolating and bounding moving
// transforms (transform_motion.h).
#include "math/transform_motion.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>

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

/// The rotation matrix of a unit quaternion in its homogeneous (purely
/// quadratic) form, which segments blend (TransformMotion::Segment).
Mat3 homogeneousMatrix(const Quaternion &q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return {{{w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z}}};
}

double dot(const Quaternion &a, const Quaternion &b) {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

/// The angle a rotates through to reach b the shorter way.
double turnAngle(const Quaternion &a, const Quaternion &b) {
  return 2 * std::acos(std::min(1.0, std::fabs(dot(a, b))));
}

/// The affine matrix of linear part l and translation t.
Mat4 place(const Mat3 &l, const Vec3 &t) {
  Mat4 m;
  m.m[3] = {0, 0, 0, 1};
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) m.m[a][b] = l[a][b];
    m.m[a][3] = t[a];
  }
  return m;
}

/// P + c Q + sn W for a segment's three fixed matrices `pqw`.
inline Mat3 blend(const std::array<Mat3, 3> &pqw, double c, double sn) {
  Mat3 m;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m[a][b] = pqw[0][a][b] + c * pqw[1][a][b] + sn * pqw[2][a][b];
  return m;
}

/// A number no other TransformMotion of the process has (from 1).
uint64_t nextSerial() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
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
  return place(product(toMatrix(parts.rotation), parts.stretch), parts.translation);
}

TransformMotion::TransformMotion(std::vector<Transform> steps)
    : steps_(std::move(steps)), serial_(nextSerial()) {
  parts_.reserve(steps_.size());
  for (const Transform &t : steps_) parts_.push_back(decompose(t.matrix()));
  for (size_t i = 0; i + 1 < parts_.size(); ++i) {
    const TransformParts &a = parts_[i], &b = parts_[i + 1];
    Segment s;
    const Quaternion &q0 = a.rotation;
    Quaternion q1 = b.rotation;
    double c = dot(q0, q1);
    if (c < 0) { // the nearer of q1 and -q1 (the same rotation)
      q1 = {-q1.w, -q1.x, -q1.y, -q1.z};
      c = -c;
    }
    // The part of q1 orthogonal to q0, normalised; none when they are the
    // same rotation (then theta = 0 and only q0 counts).
    Quaternion perp{q1.w - c * q0.w, q1.x - c * q0.x, q1.y - c * q0.y, q1.z - c * q0.z};
    const double n = std::sqrt(dot(perp, perp));
    if (n > 1e-12) {
      perp = {perp.w / n, perp.x / n, perp.y / n, perp.z / n};
      s.theta = std::atan2(n, c);
    } else {
      perp = {};
    }
    // H(c q0 + s qp) = c^2 H(q0) + s^2 H(qp) + 2 c s B(q0, qp), and c^2 =
    // (1 + cos 2u)/2, s^2 = (1 - cos 2u)/2, 2 c s = sin 2u.
    const Mat3 h0 = homogeneousMatrix(q0), hp = homogeneousMatrix(perp);
    const Mat3 sum = homogeneousMatrix({q0.w + perp.w, q0.x + perp.x, q0.y + perp.y,
                                        q0.z + perp.z});
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        s.rotation[0][r][k] = (h0[r][k] + hp[r][k]) / 2;
        s.rotation[1][r][k] = (h0[r][k] - hp[r][k]) / 2;
        s.rotation[2][r][k] = (sum[r][k] - h0[r][k] - hp[r][k]) / 2;
      }
    s.translation = a.translation;
    s.translationChange = b.translation - a.translation;
    s.stretch = a.stretch;
    // The polar decompositions of two steps with the same stretch may
    // differ in the last bits: the same within 1e-13 of the largest entry.
    double largest = 0, change = 0;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        s.stretchChange[r][k] = b.stretch[r][k] - a.stretch[r][k];
        largest = std::max(largest, std::fabs(a.stretch[r][k]));
        change = std::max(change, std::fabs(s.stretchChange[r][k]));
      }
    s.fixedStretch = change <= 1e-13 * largest;
    if (s.fixedStretch) {
      s.stretchChange = {};
      const Mat3 stretchInverse = transposed(inverseTranspose(a.stretch));
      for (int j = 0; j < 3; ++j) {
        s.linear[j] = product(s.rotation[j], a.stretch);
        s.linearInverse[j] = product(stretchInverse, transposed(s.rotation[j]));
      }
      // The blends segmentMatrix would make at every time (theta = 0: c =
      // 1, sn = 0), made once: the same arithmetic, the same bits.
      s.still = s.theta == 0;
      if (s.still) {
        s.stillLinear = blend(s.linear, 1, 0);
        s.stillInverse = blend(s.linearInverse, 1, 0);
      }
    }
    slides_ = slides_ && s.still;
    segments_.push_back(s);
  }
}

void TransformMotion::segmentMatrix(size_t i, double u, Mat4 *forward, Mat4 *inverse) const {
  const Segment &s = segments_[i];
  const Vec3 t = s.translation + s.translationChange * u;
  double c = 1, sn = 0;
  if (s.theta > 0) {
    sn = std::sin(2 * u * s.theta);
    c = std::cos(2 * u * s.theta);
  }
  if (s.still) {
    if (forward) motion_detail::placeInto(s.stillLinear, t, false, *forward);
    if (inverse) motion_detail::placeInto(s.stillInverse, t, true, *inverse);
    return;
  }
  if (s.fixedStretch) {
    if (forward) motion_detail::placeInto(blend(s.linear, c, sn), t, false, *forward);
    if (inverse) motion_detail::placeInto(blend(s.linearInverse, c, sn), t, true, *inverse);
    return;
  }
  Mat3 rotation, stretch = s.stretch;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      rotation[a][b] = s.rotation[0][a][b] + c * s.rotation[1][a][b] + sn * s.rotation[2][a][b];
      stretch[a][b] += s.stretchChange[a][b] * u;
    }
  *forward = place(product(rotation, stretch), t);
}

Transform TransformMotion::at(double time) const {
  size_t i;
  double u;
  locateMotionStep(time, steps_.size(), i, u);
  if (u == 0) return steps_[i];
  if (u == 1) return steps_[i + 1];
  Mat4 m, inverse;
  if (!segments_[i].fixedStretch) {
    segmentMatrix(i, u, &m, nullptr);
    return Transform::fromMatrix(m);
  }
  segmentMatrix(i, u, &m, &inverse);
  return Transform::fromMatrixAndInverse(m, inverse);
}

Mat4 TransformMotion::cachedInverseAt(double time, size_t i, double u) const {
  // The rays of one camera sample share its time: its shadow rays (one
  // per light cell) test the same moving entities at the same time. A
  // cache per thread, keyed by motion and time, answers those repeats (the
  // same bits: the matrix is a function of the two). It holds a tile's
  // worth: the light loop traces cell 0's shadow rays for all of a tile's
  // samples (up to Integrator::kMaxTileRays, each at its own time) before
  // cell 1's. Keyed by the motion's serial number, not its address: a
  // later frame's motion may be built where an earlier one was.
  struct Entry {
    uint64_t serial = 0;
    double time = 0;
    Mat4 inverse;
  };
  constexpr size_t kEntries = 4096; // 576 KiB, within a core's L2
  thread_local std::vector<Entry> cache(kEntries);
  uint64_t bits;
  std::memcpy(&bits, &time, sizeof bits);
  const uint64_t hash = (bits ^ (serial_ * 0x9e3779b97f4a7c15ull)) * 0xff51afd7ed558ccdull;
  Entry &e = cache[hash >> (64 - std::countr_zero(kEntries))]; // the top bits
  if (e.serial == serial_ && e.time == time) return e.inverse;
  e.serial = serial_;
  e.time = time;
  computeInverse(time, i, u, e.inverse);
  return e.inverse;
}

void TransformMotion::computeInverse(double time, size_t i, double u, Mat4 &inverse) const {
  if (u == 0) {
    inverse = steps_[i].inverseMatrix();
  } else if (u == 1) {
    inverse = steps_[i + 1].inverseMatrix();
  } else if (segments_[i].fixedStretch) {
    segmentMatrix(i, u, nullptr, &inverse);
  } else {
    inverse = at(time).inverseMatrix();
  }
}

Mat4 TransformMotion::matrixAt(double time) const {
  size_t i;
  double u;
  locateMotionStep(time, steps_.size(), i, u);
  if (u == 0) return steps_[i].matrix();
  if (u == 1) return steps_[i + 1].matrix();
  Mat4 m;
  segmentMatrix(i, u, &m, nullptr);
  return m;
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
