// Pipeline: shading. Light (lua/README.md, "Lights"): a 1 x 1 square in its local xz-plane,
// centred at its origin, split into rows x cols cells (cols along local x,
// rows along local z) and placed by worldFromLight. Each shading point
// takes one sample per cell, at the cell centre or (area) jittered inside
// it; a 1 x 1 light that is not `area` is a point light at its origin.
#pragma once

#include "math/color.h"
#include "math/random.h"
#include "math/transform.h"
#include "shading/lights/light_motion.h"
#include "shading/lights/light_sample.h"
#include "util/scene_error.h"

#include <cstdint>
#include <string>

namespace lray {

/// Where a Light's cells lie in the world (Light::Sampler): cell (row,
/// col) spans corner + cellX * [col, col + 1] + cellZ * [row, row + 1].
struct LightGrid {
  Vec3 corner, cellX, cellZ;
};

struct Light {
  static constexpr const char *kName = "Light";

  Color color{1, 1, 1};
  int rows = 1;
  int cols = 1;
  bool area = false; ///< jitter inside each cell instead of its centre
  Transform worldFromLight;
  SourceLocation loc;

  /// Shadow rays per shading point (bounded by --max-light-samples).
  uint64_t samplesPerPoint() const {
    return static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols);
  }

  /// A script-level problem with the values ("": none; each is checked alone).
  std::string invalid() const { return {}; }

  /// World-space cell grid, prepared once per frame; sampling needs no
  /// matrix product.
  class Sampler {
  public:
    explicit Sampler(const Light &light)
        : corner_(light.worldFromLight.applyPoint({-0.5, 0, -0.5})),
          cellX_(light.worldFromLight.applyVector({1.0 / light.cols, 0, 0})),
          cellZ_(light.worldFromLight.applyVector({0, 0, 1.0 / light.rows})),
          weightedColor_(light.color / (static_cast<double>(light.rows) * light.cols)),
          rows_(light.rows), cols_(light.cols), area_(light.area),
          point_(light.rows == 1 && light.cols == 1 && !light.area),
          emits_(light.rows > 0 && light.cols > 0 && !light.color.isBlack()) {
      if (point_) pointTarget_ = at(0.5, 0.5); // place's (a, b) of cell (0, 0)
    }

    /// A black or empty light can never add anything: the integrator drops it.
    bool emits() const { return emits_; }
    /// Every sample brings uniformColor() (the integrator skips the per-sample colour).
    static constexpr bool kUniformColor = true;
    const Color &uniformColor() const { return weightedColor_; }
    int sampleCount() const { return rows_ * cols_; }

    /// Sample k (cell row k / cols, column k % cols): its jitter, for area
    /// lights, drawn from `random` (x then z); the colour is colour / cells.
    LightSample sample(int k, const Vec3 &, lray::Sampler &random) const {
      // A point light's one cell: its centre, the same point every time.
      if (point_) [[likely]] {
        if (!motion_) return {pointTarget_, weightedColor_};
        return {pointTarget_ + motion_->at(random.time), weightedColor_};
      }
      double a, b;
      place(k / cols_, k % cols_, random, a, b);
      const Vec3 target = at(a, b);
      if (!motion_) return {target, weightedColor_};
      return {target + motion_->at(random.time), weightedColor_};
    }
    /// Where in cell (row, col) a sample lies, in cells along cellX (`a`)
    /// and cellZ (`b`): the centre, or for area lights jittered by `random`.
    void place(int row, int col, lray::Sampler &random, double &a, double &b) const {
      double fx = 0.5, fz = 0.5;
      if (area_) random.next2D(fx, fz);
      a = col + fx;
      b = row + fz;
    }
    bool area() const { return area_; }
    int rows() const { return rows_; }
    int cols() const { return cols_; }
    /// The cells in the world: a sample at place (a, b) lies at corner +
    /// cellX * a + cellZ * b (while the light does not move).
    LightGrid grid() const { return {corner_, cellX_, cellZ_}; }
    bool moves() const { return motion_ != nullptr; }

    /// A light that moves while the shutter is open: each sample is taken
    /// where it is at the sample's time (lray::Sampler::time).
    void setMotion(const LightMotion *motion) { motion_ = motion; }

  private:
    /// The point at place (a, b), in cells along cellX and cellZ (place).
    Vec3 at(double a, double b) const { return corner_ + cellX_ * a + cellZ_ * b; }

    Vec3 corner_; ///< world position of local (-0.5, 0, -0.5)
    Vec3 cellX_;  ///< world step of one cell along local x (length / cols)
    Vec3 cellZ_;  ///< world step of one cell along local z (length / rows)
    Color weightedColor_;
    int rows_, cols_;
    bool area_;
    bool point_; ///< one cell, not jittered: a point light (pointTarget_)
    bool emits_;
    Vec3 pointTarget_; ///< a point light's sample: at(0.5, 0.5)
    const LightMotion *motion_ = nullptr;
  };
};

} // namespace lray
