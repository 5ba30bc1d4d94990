// Pipeline: acceleration. The one interface both backends (Embree and the
// kd-tree) implement over the same primitives. Nothing outside src/accel/
// sees Embree types; render/backends.h lists the backends and runs a frame
// on each.
#pragma once

#include "math/hit.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>

namespace lray {

/// Build-time figures reported by --stats.
struct AcceleratorStats {
  double buildSeconds = 0;
  size_t memoryBytes = 0;  ///< acceleration structure + geometry it owns
  size_t primitives = 0;   ///< analytic shapes + triangles (instanced triangles counted once)
  size_t instances = 0;
};

/// A backend's queries traced alone, for bench/throughput's replay
/// (rawSeconds on each backend): closest or any hit, single rays or the
/// packets the coherent calls use.
enum class RawQuery { Closest, ClosestPackets, Occlusion, OcclusionPackets };

/// Closest-hit and any-hit queries over one frame's scene. Implementations
/// are `final`, so the integrator (a template over the concrete type,
/// instantiated in render/backends.cpp) calls them without virtual
/// dispatch. Thread-safe for concurrent queries.
class Accelerator {
public:
  virtual ~Accelerator() = default;

  /// Closest hit with t in (ray.tMin, ray.tMax); fills `hit` and returns true.
  virtual bool intersect(const Ray &ray, Hit &hit) const = 0;
  /// True if anything lies with t in (ray.tMin, ray.tMax).
  virtual bool occluded(const Ray &ray) const = 0;
  /// Coherent batch (e.g. the camera rays of a tile): found[i] = 1 and
  /// hits[i] filled where ray i hits. Embree uses 8-wide packets here.
  virtual void intersectCoherent(const Ray *rays, size_t count, Hit *hits,
                                 uint8_t *found) const = 0;
  /// Coherent batch of occlusion queries: occluded[i] = 1 where blocked.
  /// Where `blockers` is not null, blockers[i] names what was found to
  /// block ray i when that was an analytic bounded entity (its index; the
  /// integrator tests it first on the next ray of the same point, with
  /// occludedAnalytic), or is kNoEntity (clear, or blocked by something
  /// else: a triangle, an unbounded entity).
  virtual void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                                uint32_t *blockers) const = 0;

  virtual AcceleratorStats stats() const = 0;
};

} // namespace lray
