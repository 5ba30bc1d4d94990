// Pipeline: shading. SpotLight: a point light at its transform's origin
// shining along its local +z (so LookAt aims it), at full intensity inside
// the cone of half-angle `angle`, fading smoothly (smoothstep in the cosine)
// to zero at the half-angle `falloff`, dark beyond. Shadows as a point light.
#pragma once

#include "math/color.h"
#include "math/constants.h"
#include "math/random.h"
#include "math/transform.h"
#include "shading/lights/light_motion.h"
#include "shading/lights/light_sample.h"
#include "util/scene_error.h"
#include "shading/lights/light_sample.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace lray {

struct SpotLight {
  static constexpr const char *kName = "SpotLight";

  Color color{1, 1, 1};
  double angle = 30;   ///< half-angle of the full-intensity cone, degrees
  double falloff = 45; ///< half-angle where the light reaches zero, degrees
  Transform worldFromLight;
  SourceLocation loc;

  /// Shadow rays per shading point: one.
  uint64_t samplesPerPoint() const { return 1; }

  /// A script-level problem with the values ("": none); the binding
  /// checks each angle alone, this their order.
  std::string invalid() const {
    if (!(falloff < angle)) return {};
    return "SpotLight: falloff (" + formatDegrees(falloff) + ") must be at least angle (" +
           formatDegrees(angle) + ")";
  }

  static std::string formatDegrees(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }

  class Sampler {
  public:
    explicit Sampler(const SpotLight &light)
        : position_(light.worldFromLight.applyPoint({0, 0, 0})),
          axis_(normalize(light.worldFromLight.applyVector({0, 0, 1}))), color_(light.color),
          cosAngle_(std::cos(light.angle * kDegree)),
          cosFalloff_(std::cos(light.falloff * kDegree)) {}

    bool emits() const { return !color_.isBlack() && isFinite(axis_); }
    /// The colour depends on the direction: each sample carries its own.
    static constexpr bool kUniformColor = false;
    const Color &uniformColor() const { return color_; }
    int sampleCount() const { return 1; }

    /// The light at `p`: colour times the cone's factor for the direction
    /// from the light to p (black outside the falloff cone).
    LightSample sample(int, const Vec3 &p, lray::Sampler &random) const {
      if (!motion_) return {position_, color_ * factor(p)};
      // Moving: the light and its cone shifted to where it is at this time.
      const Vec3 shift = motion_->at(random.time);
      return {position_ + shift, color_ * factor(p - shift)};
    }

    /// As Light::Sampler::setMotion.
    void setMotion(const LightMotion *motion) { motion_ = motion; }

    /// 1 inside `angle`, 0 outside `falloff`, smoothstep of the cosine between.
    double factor(const Vec3 &p) const {
      Vec3 toPoint = p - position_;
      double len = length(toPoint);
      if (!(len > 0)) return 0;
      double c = dot(toPoint, axis_) / len;
      if (c >= cosAngle_) return 1;
      if (c <= cosFalloff_) return 0;
      double s = (c - cosFalloff_) / (cosAngle_ - cosFalloff_);
      return s * s * (3 - 2 * s);
    }

  private:
    Vec3 position_, axis_;
    Color color_;
    double cosAngle_, cosFalloff_;
    const LightMotion *motion_ = nullptr;
  };
};

} // namespace lray
