// Pipeline: shared math. A transform that moves while the shutter is open
// (lua/README.md, "Motion blur"): known at k evenly spaced motion steps,
// interpolated between them. Each step's matrix is split into translation,
// rotation and stretch (M = T R S, R a rotation by its polar
// decomposition), and those are interpolated: translation and stretch
// linearly, rotation by spherical interpolation of quaternions, so that a
// spinning wheel turns at an even rate and never shrinks in between (Shoemake
// and Duff 1992, as pbrt's AnimatedTransform does).
#pragma once

#include "math/bounds.h"
#include "math/motion_steps.h"
#include "math/transform.h"
#include "math/vec3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lray {

/// A unit quaternion (w + xi + yj + zk).
struct Quaternion {
  double w = 1, x = 0, y = 0, z = 0;
};

/// One motion step's matrix as translation * rotation * stretch.
struct TransformParts {
  Vec3 translation;
  Quaternion rotation;
  std::array<std::array<double, 3>, 3> stretch{}; ///< symmetric
};

/// Splits the affine `m` into TransformParts (its linear part by polar
/// decomposition; a mirroring part goes into the stretch, so the rotation
/// is proper).
TransformParts decompose(const Mat4 &m);
/// The affine matrix T R S of `parts`.
Mat4 compose(const TransformParts &parts);

namespace motion_detail {

/// The linear part `m` placed with translation `t` into `out`: after it (a
/// forward matrix) or, for an inverse, as -m t. Written straight into
/// `out`: this runs once per moving entity a ray tests.
inline void placeInto(const std::array<std::array<double, 3>, 3> &m, const Vec3 &t, bool inverse,
                      Mat4 &out) {
  const double shift[3] = {t.x, t.y, t.z};
  for (int a = 0; a < 3; ++a) {
    const double last = inverse ? -(m[a][0] * t.x + m[a][1] * t.y + m[a][2] * t.z) : shift[a];
    out.m[a] = {m[a][0], m[a][1], m[a][2], last};
  }
  out.m[3] = {0, 0, 0, 1};
}

} // namespace motion_detail

/// A transform at k >= 2 motion steps, times 0, 1/(k-1), ..., 1 of the
/// shutter.
class TransformMotion {
public:
  /// `steps`: the transform at each step (at least two, none singular).
  explicit TransformMotion(std::vector<Transform> steps);

  size_t stepCount() const { return steps_.size(); }
  /// Whether it only slides (no turn, the same stretch, at every step):
  /// then inverseMatrixAt is a few products.
  bool slides() const { return slides_; }
  const Transform &step(size_t i) const { return steps_[i]; }

  /// The transform at `time` in [0, 1] (clamped): exactly step i's at its
  /// own time, interpolated parts between.
  Transform at(double time) const;
  /// Only the matrix of at(time) (no inverse): cameras.
  Mat4 matrixAt(double time) const;
  /// Only the inverse matrix of at(time), the same bits: a ray test.
  /// Inline for a segment that only slides (a few products, per test of a
  /// moving entity); the others go to a cache.
  Mat4 inverseMatrixAt(double time) const {
    size_t i;
    double u;
    locateMotionStep(time, steps_.size(), i, u);
    const Segment &s = segments_[i];
    if (!s.still || u == 0 || u == 1) return cachedInverseAt(time, i, u);
    Mat4 inverse;
    motion_detail::placeInto(s.stillInverse, s.translation + s.translationChange * u, true,
                             inverse);
    return inverse;
  }

  /// Bounds of `objectBox` placed by the transform over the times [t0, t1]:
  /// the boxes at evenly spaced times, widened by how far any point of the
  /// box can move between two of them (its speed bound, see the .cpp).
  Bounds3 sweptBounds(const Bounds3 &objectBox, double t0, double t1) const;
  /// Bounds over the whole shutter from a function giving tight world
  /// bounds for one transform (an analytic shape's): the same times and
  /// widening as sweptBounds, with `objectBox` for the speed bound.
  template <class BoundsAt>
  Bounds3 sweptBounds(const Bounds3 &objectBox, double t0, double t1, BoundsAt boundsAt) const;

  /// The placed object's bounds at motion step `step` (from `boundsAt`, as
  /// for sweptBounds), widened so that the linear blend of two neighbouring
  /// steps' boxes holds the object over the whole segment between them (a
  /// backend that blends step bounds by the ray's time, as Embree does).
  /// Each segment next to the step is sampled: the widening is the most a
  /// sampled box pokes out of the blend, plus how far the object and the
  /// blend can move between two samples.
  template <class BoundsAt>
  Bounds3 stepBounds(const Bounds3 &objectBox, size_t step, BoundsAt boundsAt) const;

private:
  using Mat3 = std::array<std::array<double, 3>, 3>;
  /// What interpolating over segment i (steps i and i + 1) needs, set up
  /// once. The slerp from q0 to the nearer of +-q1 is q(u) = cos(u theta)
  /// q0 + sin(u theta) qPerp, and a unit quaternion's matrix is quadratic
  /// in it, so the rotation is R(u) = P + cos(2 u theta) Q + sin(2 u theta)
  /// W for three fixed matrices: one sincos and a blend per time.
  struct Segment {
    double theta = 0;
    Vec3 translation, translationChange;
    std::array<Mat3, 3> rotation{}; ///< P, Q, W
    Mat3 stretch{}, stretchChange{};
    /// The stretch is the same at both ends up to rounding (a turn, a
    /// slide: the usual case): then the linear part R(u) S and its inverse
    /// S^-1 R(u)^T blend three fixed matrices each too, and the
    /// transform's inverse needs no solve.
    bool fixedStretch = false;
    std::array<Mat3, 3> linear{}, linearInverse{};
    /// No turn either (theta = 0, a slide): the linear part and its
    /// inverse are fixed matrices, and only the translation moves.
    bool still = false;
    Mat3 stillLinear{}, stillInverse{};
  };
  /// inverseMatrixAt through a cache; `i` and `u` say where `time` falls
  /// (locateMotionStep).
  Mat4 cachedInverseAt(double time, size_t i, double u) const;
  /// inverseMatrixAt without its cache, written into `inverse`.
  void computeInverse(double time, size_t i, double u, Mat4 &inverse) const;
  /// Segment i's matrix at fraction u (when `forward` is given: always
  /// without a fixed stretch) and, for a fixed stretch, its inverse (when
  /// `inverse` is).
  void segmentMatrix(size_t i, double u, Mat4 *forward, Mat4 *inverse) const;
  /// How fast a point of `objectBox` can move over segment i (distance per
  /// whole segment).
  double segmentSpeed(size_t segment, const Bounds3 &objectBox) const;

  std::vector<Transform> steps_;
  std::vector<TransformParts> parts_;
  std::vector<Segment> segments_;
  uint64_t serial_; ///< unique in the process: inverseMatrixAt's cache key
  bool slides_ = true;
};

template <class BoundsAt>
Bounds3 TransformMotion::sweptBounds(const Bounds3 &objectBox, double t0, double t1,
                                     BoundsAt boundsAt) const {
  Bounds3 out;
  if (objectBox.empty()) return out;
  const size_t segments = steps_.size() - 1;
  const Vec3 extent = objectBox.hi - objectBox.lo;
  const double size = std::max({extent.x, extent.y, extent.z, 1e-300});
  double gap = 0;
  for (size_t i = 0; i < segments; ++i) {
    const double s0 = double(i) / segments, s1 = double(i + 1) / segments;
    if (s1 < t0 || s0 > t1) continue;
    // Samples enough for the widening to stay within 1/200 of the box's
    // size (8 to 256 of them).
    const double speed = segmentSpeed(i, objectBox);
    const int samples = static_cast<int>(std::clamp(std::ceil(speed / (0.01 * size)), 8.0, 256.0));
    gap = std::max(gap, speed / samples / 2 * (1 + 1e-9));
    for (int j = 0; j <= samples; ++j) {
      const double t = s0 + (s1 - s0) * j / samples;
      if (t >= t0 && t <= t1) out.extend(boundsAt(at(t)));
    }
  }
  out.extend(boundsAt(at(t0)));
  out.extend(boundsAt(at(t1)));
  const Vec3 pad(gap, gap, gap);
  return {out.lo - pad, out.hi + pad};
}

template <class BoundsAt>
Bounds3 TransformMotion::stepBounds(const Bounds3 &objectBox, size_t step,
                                    BoundsAt boundsAt) const {
  if (objectBox.empty()) return {};
  const size_t segments = steps_.size() - 1;
  const Bounds3 here = boundsAt(steps_[step]);
  const Vec3 extent = objectBox.hi - objectBox.lo;
  const double size = std::max({extent.x, extent.y, extent.z, 1e-300});
  double pad = 0;
  for (size_t i = step == 0 ? 0 : step - 1; i <= std::min(step, segments - 1); ++i) {
    const Bounds3 a = i == step ? here : boundsAt(steps_[i]);
    const Bounds3 b = i == step ? boundsAt(steps_[i + 1]) : here;
    // How far the object and the blend's faces move over the segment.
    double speed = segmentSpeed(i, objectBox);
    for (int k = 0; k < 3; ++k)
      speed += std::max(std::fabs(b.lo[k] - a.lo[k]), std::fabs(b.hi[k] - a.hi[k]));
    const int samples = static_cast<int>(std::clamp(std::ceil(speed / (0.01 * size)), 8.0, 256.0));
    double poke = 0;
    for (int j = 1; j < samples; ++j) {
      const double u = double(j) / samples;
      const Bounds3 box = boundsAt(at((double(i) + u) / double(segments)));
      for (int k = 0; k < 3; ++k)
        poke = std::max({poke, a.lo[k] + (b.lo[k] - a.lo[k]) * u - box.lo[k],
                         box.hi[k] - (a.hi[k] + (b.hi[k] - a.hi[k]) * u)});
    }
    // The blend is read at times up to 1e-6 of a segment off the ray's
    // (a backend's float time).
    pad = std::max(pad, poke + speed * (0.5 / samples + 1e-6));
  }
  pad *= 1 + 1e-9;
  return {here.lo - Vec3(pad, pad, pad), here.hi + Vec3(pad, pad, pad)};
}

} // namespace lray
