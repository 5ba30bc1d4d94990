// Pipeline: acceleration (both backends). A moving entity's bounds at a
// ray's time: the blend of its bounds at the two motion steps around it
// (stepWorldBounds), which holds the entity at every time between them
// (lua/README.md, "Motion blur"). Before the entity's transform at the
// ray's time is computed (the costly part of a moving entity's test), the
// ray is tested against that box. The kd-tree bounds a moving entity over
// the whole shutter, so a ray meets it in every leaf its sweep touches;
// Embree calls a user geometry's test for every primitive of a leaf it
// reaches, with every ray of a packet that reached the leaf.
#pragma once

#include "geometry/shape.h"
#include "math/bounds.h"
#include "math/motion_steps.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace lray {

class MovingBoxes {
public:
  MovingBoxes() = default;
  /// The step bounds of every bounded entity of `scene` that moves.
  explicit MovingBoxes(const Scene &scene) {
    if (scene.motionSteps < 2) return;
    steps_ = static_cast<size_t>(scene.motionSteps);
    for (uint32_t i = 0; i < scene.entities.size(); ++i) {
      const Entity &e = scene.entities[i];
      if (!e.moves() || !shapeBounded(e)) continue;
      if (first_.empty()) first_.assign(scene.entities.size(), kNone);
      first_[i] = static_cast<uint32_t>(boxes_.size());
      for (size_t s = 0; s < steps_; ++s) boxes_.push_back(stepWorldBounds(e, s));
    }
  }

  /// Whether entity `entity` moves (has step bounds here).
  bool moves(uint32_t entity) const { return !first_.empty() && first_[entity] != kNone; }
  /// Its bounds at motion step `step` (moves(entity)).
  const Bounds3 &stepBox(uint32_t entity, size_t step) const {
    return boxes_[first_[entity] + step];
  }

  /// True when `ray`, over [ray.tMin, tMax], surely misses entity `entity`
  /// at the ray's time; false for an entity that does not move.
  bool misses(uint32_t entity, const Ray &ray, double tMax) const {
    if (!moves(entity)) return false;
    size_t i;
    double u;
    locateMotionStep(ray.time, steps_, i, u);
    const Bounds3 &a = boxes_[first_[entity] + i], &b = boxes_[first_[entity] + i + 1];
    const double o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
    double tNear = ray.tMin, tFar = tMax;
    for (int k = 0; k < 3; ++k) {
      double lo = a.lo[k] + (b.lo[k] - a.lo[k]) * u, hi = a.hi[k] + (b.hi[k] - a.hi[k]) * u;
      // Widened far beyond the rounding of the blend and of the slab's t.
      const double pad = 1e-9 * (std::fabs(lo) + std::fabs(hi));
      lo -= pad;
      hi += pad;
      if (d[k] == 0) {
        if (o[k] < lo || o[k] > hi) return true;
        continue;
      }
      // A product with the reciprocal, not two divisions (a division's
      // latency, per axis per test, was most of this test's time); its
      // extra rounding is as far within the padding as the division's.
      const double inverse = 1 / d[k];
      double t0 = (lo - o[k]) * inverse, t1 = (hi - o[k]) * inverse;
      if (t0 > t1) std::swap(t0, t1);
      tNear = std::max(tNear, t0);
      tFar = std::min(tFar, t1);
      if (tNear > tFar) return true;
    }
    return false;
  }

private:
  static constexpr uint32_t kNone = ~0u;
  size_t steps_ = 0;
  std::vector<uint32_t> first_; ///< per entity: its step 0 box in boxes_, or kNone
  std::vector<Bounds3> boxes_;
};

} // namespace lray
