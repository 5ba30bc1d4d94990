// Pipeline: shading. Per-thread counters of rays traced by kind, summed
// once per tile (no shared atomics on the hot path); reported by --stats.
#pragma once

#include <cstdint>

namespace lray {

struct RayCounts {
  uint64_t camera = 0;
  uint64_t shadow = 0;
  /// Shadow rays not traced because nothing could block them (shadow_shaft.h).
  uint64_t shadowSkipped = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  /// The path tracer's diffusely scattered rays (path_integrator.h).
  uint64_t diffuse = 0;
  /// The path tracer's paths and the surfaces they met (scattered at or
  /// ended on): their mean length for --stats.
  uint64_t paths = 0;
  uint64_t pathVertices = 0;
  /// Samples whose colour came out NaN or Inf (replaced by black; must stay 0).
  uint64_t nonFinite = 0;

  RayCounts &operator+=(const RayCounts &o) {
    camera += o.camera;
    shadow += o.shadow;
    shadowSkipped += o.shadowSkipped;
    reflection += o.reflection;
    refraction += o.refraction;
    diffuse += o.diffuse;
    paths += o.paths;
    pathVertices += o.pathVertices;
    nonFinite += o.nonFinite;
    return *this;
  }
};

} // namespace lray
