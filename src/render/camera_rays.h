// Pipeline: render. Turns image-plane positions into world-space camera rays
// for the cameras of lua/README.md ("Perspective", "Orthographic",
// "Spherical").
#pragma once

#include "math/transform.h"
#include "math/constants.h"
#include "math/lanes.h"
#include "math/motion_steps.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace lray {

/// Generates primary rays. Pixel (0,0) is the top-left of the image.
/// Perspective: the image plane at distance 1 spans the horizontal field of
/// view, with height width/aspect; with an aperture, rays leave a point of
/// the lens disc and pass through the point of the focal plane (z =
/// focal distance) the pinhole ray meets (pbrt's thin lens). Orthographic:
/// rays along +z from the points of a width x width/aspect rectangle.
/// Spherical: longitude -180..180 degrees across the image (0 at its
/// centre, along +z; +x to the right), latitude 90..-90 down it. A moving
/// camera (Camera::motion) is placed where it is at the ray's time.
class CameraRays {
public:
  /// `timed`: the shutter is open (Scene::motionSteps): rays get times.
  CameraRays(const Camera &camera, int imageWidth, int imageHeight, bool timed = false)
      : worldFromCamera_(camera.worldFromCamera), kind_(camera.kind), width_(imageWidth),
        height_(imageHeight), aperture_(camera.aperture), focal_(camera.focalDistance),
        motion_(camera.motion.get()), timed_(timed) {
    if (motion_) tabulateMotion();
    halfWidth_ = camera.kind == CameraKind::Orthographic ? camera.width / 2
                                                         : std::tan(camera.fov * 0.5 * kPi / 180.0);
    halfHeight_ = halfWidth_ / camera.aspect;
    origin_ = worldFromCamera_.applyPoint({0, 0, 0});
  }

  /// Whether rays get a time in the shutter (generate's time).
  bool timed() const { return timed_; }

  /// Whether rays depend on a lens sample (generate's lensU, lensV).
  bool hasLens() const { return kind_ == CameraKind::Perspective && aperture_ > 0; }

  /// The ray through image position (px, py), in pixels from the top-left
  /// corner (px in [0, width], py in [0, height]), through lens sample
  /// (lensU, lensV) in [0,1)^2 when hasLens(), at shutter time `time`.
  /// Direction is not unit length.
  Ray generate(double px, double py, double lensU = 0.5, double lensV = 0.5, float time = 0) const {
    if (!motion_) [[likely]]
      return generateWith(worldFromCamera_, origin_, px, py, lensU, lensV, time);
    return generateMoving(px, py, lensU, lensV, time);
  }

  /// generate(px[j], py[j]) into out[j] for j < n. A still pinhole
  /// camera's (most frames') go four at a time: the same operations lane by
  /// lane, so the same rays bit for bit, with their two divisions and the
  /// direction's products in vector instructions that overlap (one at a
  /// time, each ray's divisions waited on the last's).
  void generateMany(const double *px, const double *py, size_t n, Ray *out) const {
    size_t j = 0;
    if (kind_ == CameraKind::Perspective && !hasLens() && !motion_)
      for (; j + lanes::kWidth <= n; j += lanes::kWidth) pinholeLanes(px + j, py + j, out + j);
    for (; j < n; ++j) out[j] = generate(px[j], py[j]);
  }

private:
  /// generateWith's pinhole ray, four at a time (generateMany).
  [[gnu::always_inline]] void pinholeLanes(const double *px, const double *py, Ray *out) const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    lanes::Lanes x, y;
    lanes::load(px, x);
    lanes::load(py, y);
    const double width = width_, height = height_;
    const lanes::Lanes cx = (2 * x / width - 1) * halfWidth_;
    const lanes::Lanes cy = (1 - 2 * y / height) * halfHeight_;
    // affineVector(m, {cx, cy, 1}): m[r][2] * 1 is m[r][2].
    const auto &m = worldFromCamera_.matrix().m;
    const lanes::Lanes dx = m[0][0] * cx + m[0][1] * cy + m[0][2];
    const lanes::Lanes dy = m[1][0] * cx + m[1][1] * cy + m[1][2];
    const lanes::Lanes dz = m[2][0] * cx + m[2][1] * cy + m[2][2];
    // Field by field: a whole Ray built first went through the stack,
    // stored in pieces and read back at once, stalling on each.
    for (int k = 0; k < lanes::kWidth; ++k) {
      Ray &r = out[k];
      r.o = origin_;
      r.d.x = dx[k];
      r.d.y = dy[k];
      r.d.z = dz[k];
      r.tMin = 0;
      r.tMax = kInf;
      r.time = 0;
    }
  }

  /// A moving camera's placement (Camera::motion) at kTableSteps + 1 even
  /// times per motion step, blended linearly between neighbours: each camera
  /// ray needs it, and the interpolation itself (a sincos, a quaternion's
  /// matrix, a product) cost a simple scene more than its rays. The blend of
  /// two rotations 1/512 of a segment's turn apart is within (turn / 512)^2
  /// / 8 of the turn between them: a millionth for a quarter turn a step.
  static constexpr int kTableSteps = 512;

  /// A placement's affine rows (its matrix without the constant last
  /// row): what a camera ray reads of it.
  struct Pose {
    std::array<std::array<double, 4>, 3> m;
  };

  void tabulateMotion() {
    const size_t entries = (motion_->stepCount() - 1) * kTableSteps + 1;
    path_.resize(entries);
    for (size_t i = 0; i < entries; ++i) {
      const Mat4 m = motion_->matrixAt(static_cast<double>(i) / static_cast<double>(entries - 1));
      for (int r = 0; r < 3; ++r) path_[i].m[r] = m.m[r];
    }
  }

  /// generate for a moving camera (Camera::motion): placed at `time`.
  /// Flattened: GCC called the placement's two products out of line, once
  /// each per camera ray.
  [[gnu::noinline, gnu::flatten]] Ray generateMoving(double px, double py, double lensU,
                                                     double lensV, float time) const {
    size_t i;
    double f;
    locateMotionStep(time, path_.size(), i, f); // the table's entries as steps
    MatrixPlacement moved;
    const Pose &a = path_[i], &b = path_[i + 1];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        moved.m.m[r][c] = a.m[r][c] * (1 - f) + b.m[r][c] * f;
    // The camera's centre: the translation itself, not the matrix applied to
    // (0, 0, 0) (the same values, up to the sign of a zero).
    const Vec3 centre(moved.m.m[0][3], moved.m.m[1][3], moved.m.m[2][3]);
    return generateWith(moved, centre, px, py, lensU, lensV, time);
  }

  /// A placement by a bare matrix (a moving camera's, at one time).
  struct MatrixPlacement {
    Mat4 m;
    Vec3 applyPoint(const Vec3 &p) const { return affinePoint(m, p); }
    Vec3 applyVector(const Vec3 &v) const { return affineVector(m, v); }
  };

  template <class Placement>
  Ray generateWith(const Placement &worldFromCamera, const Vec3 &origin, double px, double py,
                   double lensU, double lensV, float time) const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double cx = (2 * px / width_ - 1) * halfWidth_;
    const double cy = (1 - 2 * py / height_) * halfHeight_;
    switch (kind_) {
    case CameraKind::Orthographic:
      return {worldFromCamera.applyPoint({cx, cy, 0}), worldFromCamera.applyVector({0, 0, 1}), 0,
              kInf, time};
    case CameraKind::Spherical: {
      const double longitude = (px / width_ - 0.5) * 2 * kPi;
      const double latitude = (0.5 - py / height_) * kPi;
      const double c = std::cos(latitude);
      return {origin,
              worldFromCamera.applyVector(
                  {c * std::sin(longitude), std::sin(latitude), c * std::cos(longitude)}),
              0, kInf, time};
    }
    case CameraKind::Perspective:
      break;
    }
    if (!hasLens()) return {origin, worldFromCamera.applyVector({cx, cy, 1}), 0, kInf, time};
    double lx, ly;
    concentricDisc(lensU, lensV, lx, ly);
    const Vec3 lens{aperture_ * lx, aperture_ * ly, 0};
    const Vec3 focus{cx * focal_, cy * focal_, focal_};
    return {worldFromCamera.applyPoint(lens), worldFromCamera.applyVector(focus - lens), 0, kInf,
            time};
  }

  /// Shirley and Chiu's concentric map of [0,1)^2 onto the unit disc: it
  /// keeps the strata of the lens samples compact.
  static void concentricDisc(double u, double v, double &x, double &y) {
    const double a = 2 * u - 1, b = 2 * v - 1;
    if (a == 0 && b == 0) {
      x = y = 0;
      return;
    }
    double r, phi;
    if (std::abs(a) > std::abs(b)) {
      r = a;
      phi = kPi / 4 * (b / a);
    } else {
      r = b;
      phi = kPi / 2 - kPi / 4 * (a / b);
    }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
  }

  Transform worldFromCamera_;
  CameraKind kind_;
  int width_, height_;
  double halfWidth_ = 1, halfHeight_ = 1;
  double aperture_, focal_;
  Vec3 origin_;
  const TransformMotion *motion_;
  std::vector<Pose> path_; ///< a moving camera's placement table (tabulateMotion)
  bool timed_;
};

} // namespace lray
