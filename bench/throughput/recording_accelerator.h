// bench/throughput: an accelerator that passes every query to another and
// keeps a copy of its rays, by the call that traced them, so that they can
// be traced again through Embree alone (EmbreeAccelerator::rawSeconds).
#pragma once

#include "accel/accelerator.h"

#include <tbb/enumerable_thread_specific.h>

#include <vector>

namespace lray {

/// The rays of a render, by the query that traced them.
struct RecordedRays {
  std::vector<Ray> camera;    ///< intersectCoherent: camera rays, 8-wide packets
  std::vector<Ray> secondary; ///< intersect: reflection, refraction, path bounces
  std::vector<Ray> shadow;    ///< occluded: single shadow rays
  std::vector<Ray> shadowPackets; ///< occludedCoherent: a tile's shadow rays, packets
};

template <class Inner> class RecordingAccelerator final : public Accelerator {
public:
  explicit RecordingAccelerator(const Inner &inner) : inner_(inner) {}

  bool intersect(const Ray &ray, Hit &hit) const override {
    rays_.local().secondary.push_back(ray);
    return inner_.intersect(ray, hit);
  }
  bool occluded(const Ray &ray) const override {
    rays_.local().shadow.push_back(ray);
    return inner_.occluded(ray);
  }
  void intersectCoherent(const Ray *rays, size_t count, Hit *hits,
                         uint8_t *found) const override {
    auto &kept = rays_.local().camera;
    kept.insert(kept.end(), rays, rays + count);
    inner_.intersectCoherent(rays, count, hits, found);
  }
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                        uint32_t *blockers) const override {
    auto &kept = rays_.local().shadowPackets;
    kept.insert(kept.end(), rays, rays + count);
    inner_.occludedCoherent(rays, count, occluded, blockers);
  }
  AcceleratorStats stats() const override { return inner_.stats(); }

  /// Every thread's rays together.
  RecordedRays recorded() const {
    RecordedRays all;
    for (const RecordedRays &r : rays_) {
      all.camera.insert(all.camera.end(), r.camera.begin(), r.camera.end());
      all.secondary.insert(all.secondary.end(), r.secondary.begin(), r.secondary.end());
      all.shadow.insert(all.shadow.end(), r.shadow.begin(), r.shadow.end());
      all.shadowPackets.insert(all.shadowPackets.end(), r.shadowPackets.begin(),
                               r.shadowPackets.end());
    }
    return all;
  }

private:
  const Inner &inner_;
  mutable tbb::enumerable_thread_specific<RecordedRays> rays_;
};

} // namespace lray
