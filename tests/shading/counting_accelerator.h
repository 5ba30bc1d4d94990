// Tests for src/shading: a BruteForceAccelerator that counts the shadow
// rays given to occludedCoherent, keeps each call's, and may keep their
// blockers to itself.
#pragma once

#include "shading/brute_force_accelerator.h"

#include <algorithm>
#include <vector>

namespace lray::testing {

/// A BruteForceAccelerator with the shared shape code, counting the shadow
/// rays given to occludedCoherent and those found blocked, each call's rays
/// kept (calls); with `nameBlockers` false it names no blocker (as for a
/// mesh), so the integrator has no occluder to test first.
class CountingAccelerator final : public Accelerator {
public:
  CountingAccelerator(const Scene &scene, bool nameBlockers)
      : inner_(scene, true), nameBlockers_(nameBlockers) {}
  bool intersect(const Ray &ray, Hit &hit) const override { return inner_.intersect(ray, hit); }
  bool occluded(const Ray &ray) const override { return inner_.occluded(ray); }
  void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const override {
    inner_.intersectCoherent(rays, count, hits, found);
  }
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                        uint32_t *blockers) const override {
    calls.emplace_back(rays, rays + count);
    inner_.occludedCoherent(rays, count, occluded, nameBlockers_ ? blockers : nullptr);
    if (!nameBlockers_ && blockers) std::fill_n(blockers, count, kNoEntity);
    for (size_t i = 0; i < count; ++i) blockedRays += occluded[i];
  }
  AcceleratorStats stats() const override { return {}; }
  /// The shadow rays given to occludedCoherent, over all calls.
  size_t coherentShadowRays() const {
    size_t n = 0;
    for (const std::vector<Ray> &call : calls) n += call.size();
    return n;
  }
  mutable size_t blockedRays = 0;
  mutable std::vector<std::vector<Ray>> calls;

private:
  BruteForceAccelerator inner_;
  bool nameBlockers_;
};

} // namespace lray::testing
