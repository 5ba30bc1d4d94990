// Pipeline: render. Turns image-plane positions into world-space camera rays
// for the Perspective camera of lua/README.md, "Scene and camera".
#pragma once

#include "math/constants.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <cmath>

namespace lray {

/// Generates primary rays. Pixel (0,0) is the top-left of the image; the
/// image plane spans the horizontal field of view, with height width/aspect.
class CameraRays {
public:
  CameraRays(const Camera &camera, int imageWidth, int imageHeight)
      : worldFromCamera_(camera.worldFromCamera), width_(imageWidth), height_(imageHeight) {
    halfWidth_ = std::tan(camera.fov * 0.5 * kPi / 180.0);
    halfHeight_ = halfWidth_ / camera.aspect;
    origin_ = worldFromCamera_.applyPoint({0, 0, 0});
  }

  /// The ray through image position (px, py), in pixels from the top-left
  /// corner (px in [0, width], py in [0, height]). Direction is not unit length.
  Ray generate(double px, double py) const {
    double cx = (2 * px / width_ - 1) * halfWidth_;
    double cy = (1 - 2 * py / height_) * halfHeight_;
    return {origin_, worldFromCamera_.applyVector({cx, cy, 1}), 0,
            std::numeric_limits<double>::infinity()};
  }

private:
  Transform worldFromCamera_;
  int width_, height_;
  double halfWidth_ = 1, halfHeight_ = 1;
  Vec3 origin_;
};

} // namespace lray
