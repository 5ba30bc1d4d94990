// Pipeline: acceleration. The one interface both backends (Embree and the
// kd-tree) implement over the same primitives. Nothing outside src/accel/
// sees Embree types.
#pragma once

#include "geometry/hit.h"
#include "math/ray.h"
#include "render/frame_settings.h"
#include "scene/scene.h"
#include "shading/ray_counts.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace lray {

class Film;
class ImageCache;

/// The backends this build has (accelerator.cpp lists them with their names).
enum class BackendKind { Embree, KdTree };

class Accelerator;

/// One backend: its command-line name, its kind and how to build it.
struct BackendEntry {
  const char *name;
  BackendKind kind;
  std::unique_ptr<Accelerator> (*make)(const Scene &scene);
};

/// Every backend, the default first; the only list of them.
std::span<const BackendEntry> backends();

/// The name of `kind` ("embree", "kdtree").
std::string backendName(BackendKind kind);

/// Build-time figures reported by --stats.
struct AcceleratorStats {
  double buildSeconds = 0;
  size_t memoryBytes = 0;  ///< acceleration structure + geometry it owns
  size_t primitives = 0;   ///< analytic shapes + triangles (instanced triangles counted once)
  size_t instances = 0;
};

/// Closest-hit and any-hit queries over one frame's scene. Implementations
/// are `final`, so the integrator (a template over the concrete type) calls
/// them without virtual dispatch. Thread-safe for concurrent queries.
class Accelerator {
public:
  virtual ~Accelerator() = default;

  /// Closest hit with t in (ray.tMin, ray.tMax); fills `hit` and returns true.
  virtual bool intersect(const Ray &ray, Hit &hit) const = 0;
  /// True if anything lies with t in (ray.tMin, ray.tMax).
  virtual bool occluded(const Ray &ray) const = 0;
  /// Coherent batch (e.g. the camera rays of a tile): found[i] = 1 and
  /// hits[i] filled where ray i hits. Embree uses 8-wide packets here.
  virtual void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const = 0;
  /// Coherent batch of occlusion queries: occluded[i] = 1 where blocked.
  virtual void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded) const = 0;

  virtual AcceleratorStats stats() const = 0;

  /// Renders one frame of `scene` (the scene this was built over) into
  /// `film`: the tile loop and integrator instantiated for the concrete
  /// backend (render/tile_renderer.h), so every query below this one
  /// virtual call is direct. Adds the rays traced to `counts`.
  virtual void render(const Scene &scene, const ImageCache &images, const FrameSettings &settings,
                      Film &film, RayCounts &counts, const ProgressFn &progress) const = 0;
};

/// Builds the chosen backend over `scene` (which must outlive the result).
std::unique_ptr<Accelerator> makeAccelerator(BackendKind kind, const Scene &scene);
/// The same by name; std::invalid_argument for a name backends() lacks.
std::unique_ptr<Accelerator> makeAccelerator(std::string_view name, const Scene &scene);

} // namespace lray
