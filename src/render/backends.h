// Pipeline: render. The table of acceleration backends (src/accel/) and of
// the integrators (src/shading/) each frame can be rendered with: the one
// place where a backend is paired with an integrator and the tile loop is
// instantiated for the pair, so every ray query below a frame's one call
// through this table is a direct call (no virtual call per ray).
#pragma once

#include "accel/accelerator.h"
#include "render/film.h"
#include "render/frame_settings.h"
#include "scene/scene.h"
#include "shading/ray_counts.h"

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace lray {

class ImageCache;

/// The backends this build has, in the order of backends().
enum class BackendKind { Embree, KdTree };

/// Renders one frame of `scene` into `film` with the accelerator built over
/// it, adding the rays traced to `counts`.
using RenderFn = void (*)(const Accelerator &accel, const Scene &scene, const ImageCache &images,
                          const FrameSettings &settings, Film &film, RayCounts &counts,
                          const ProgressFn &progress);

/// One backend: its command-line name, its kind, how to build it, and its
/// tile loop for each IntegratorKind (in the enum's order).
struct BackendEntry {
  const char *name;
  BackendKind kind;
  std::unique_ptr<Accelerator> (*make)(const Scene &scene);
  /// Whether `accel` was built by this entry's `make`.
  bool (*built)(const Accelerator &accel);
  std::array<RenderFn, kIntegratorKinds> render;
};

/// Every backend, the default first; the only list of them.
std::span<const BackendEntry> backends();

/// The name of `kind` ("embree", "kdtree").
std::string backendName(BackendKind kind);

/// Builds the chosen backend over `scene` (which must outlive the result);
/// first charges the build to Scene::memory, throwing SceneError at the
/// entity that asks for most of it when it would pass --render-memory.
std::unique_ptr<Accelerator> makeAccelerator(BackendKind kind, const Scene &scene);
/// The same by name; std::invalid_argument for a name backends() lacks.
std::unique_ptr<Accelerator> makeAccelerator(std::string_view name, const Scene &scene);

/// The entry whose `make` built `accel`; std::invalid_argument for an
/// accelerator of no entry (a test's own, which renders itself).
const BackendEntry &backendOf(const Accelerator &accel);

} // namespace lray
