// Pipeline: render. See backends.h. Adding a backend: its folder under
// src/accel/ and one line in kBackends; adding an integrator: its
// IntegratorKind and one column in each line's render table.
#include "render/backends.h"

#include "accel/embree/embree_accelerator.h"
#include "accel/kdtree/kdtree_accelerator.h"
#include "render/tile_renderer_impl.h"
#include "shading/path_integrator_impl.h"

#include <cassert>
#include <stdexcept>
#include <unordered_set>

namespace lray {

namespace {

template <class Accel> std::unique_ptr<Accelerator> make(const Scene &scene) {
  return std::make_unique<Accel>(scene);
}

template <class Accel> bool built(const Accelerator &accel) {
  return dynamic_cast<const Accel *>(&accel) != nullptr;
}

/// The tile loop of `Integ` over `Accel`: the accelerator's type is known
/// from here down.
template <class Accel, template <class> class Integ>
void render(const Accelerator &accel, const Scene &scene, const ImageCache &images,
            const FrameSettings &settings, Film &film, RayCounts &counts,
            const ProgressFn &progress) {
  renderTiles<Integ<Accel>>(static_cast<const Accel &>(accel), scene, images, settings, film,
                            counts, progress);
}

template <class Accel>
constexpr BackendEntry entry(const char *name, BackendKind kind) {
  return {name, kind, &make<Accel>, &built<Accel>,
          {&render<Accel, Integrator>, &render<Accel, PathIntegrator>}};
}

constexpr BackendEntry kBackends[] = {
    entry<EmbreeAccelerator>("embree", BackendKind::Embree),
    entry<KdTreeAccelerator>("kdtree", BackendKind::KdTree),
};

const BackendEntry &entry(BackendKind kind) {
  for (const BackendEntry &b : kBackends)
    if (b.kind == kind) return b;
  assert(false && "a BackendKind without an entry in kBackends");
  return kBackends[0];
}

/// What building either backend over a scene may take at its peak, per
/// triangle of each distinct mesh (instances share one tree) and per entity
/// (an analytic shape, a CSG tree or a mesh instance): about three times
/// what the finished structures hold (bench/README.md, memory), for the
/// builders' working arrays.
constexpr uint64_t kBuildBytesPerTriangle = 200, kBuildBytesPerEntity = 400;

/// Charges the build against the frame's render memory budget before it
/// starts, blaming the entity that asks for most of it.
void chargeAccelerator(const Scene &scene) {
  if (scene.memory.limit() == 0 || scene.entities.empty()) return;
  std::unordered_set<const MeshData *> meshes;
  uint64_t triangles = 0, bytes = 0, largest = 0;
  const Entity *blamed = &scene.entities.front();
  for (const Entity &e : scene.entities) {
    uint64_t own = kBuildBytesPerEntity;
    if (e.mesh && meshes.insert(e.mesh.get()).second) {
      triangles += e.mesh->triangles.size();
      own += e.mesh->triangles.size() * kBuildBytesPerTriangle;
    }
    bytes += own;
    if (own > largest) largest = own, blamed = &e;
  }
  MemoryBudget budget = scene.memory;
  budget.charge(bytes,
                "the acceleration structure of " + std::to_string(scene.entities.size()) +
                    " entities and " + std::to_string(triangles) + " triangles",
                blamed->loc);
}

} // namespace

std::span<const BackendEntry> backends() { return kBackends; }

std::string backendName(BackendKind kind) { return entry(kind).name; }

std::unique_ptr<Accelerator> makeAccelerator(BackendKind kind, const Scene &scene) {
  chargeAccelerator(scene);
  return entry(kind).make(scene);
}

std::unique_ptr<Accelerator> makeAccelerator(std::string_view name, const Scene &scene) {
  for (const BackendEntry &b : kBackends)
    if (name == b.name) {
      chargeAccelerator(scene);
      return b.make(scene);
    }
  throw std::invalid_argument("unknown backend '" + std::string(name) + "'");
}

const BackendEntry &backendOf(const Accelerator &accel) {
  for (const BackendEntry &b : kBackends)
    if (b.built(accel)) return b;
  throw std::invalid_argument("an accelerator that no backend of render/backends.cpp built");
}

} // namespace lray
