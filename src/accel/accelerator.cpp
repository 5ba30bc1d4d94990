// Pipeline: acceleration. The one list of backends, chosen by name at run
// time: the only code outside each backend's own folder that names them.
#include "accel/accelerator.h"

#include "accel/embree/embree_accelerator.h"
#include "accel/kdtree/kdtree_accelerator.h"

#include <cassert>
#include <stdexcept>

namespace lray {

namespace {

template <class A> std::unique_ptr<Accelerator> make(const Scene &scene) {
  return std::make_unique<A>(scene);
}

constexpr BackendEntry kBackends[] = {
    {"embree", BackendKind::Embree, &make<EmbreeAccelerator>},
    {"kdtree", BackendKind::KdTree, &make<KdTreeAccelerator>},
};

const BackendEntry &entry(BackendKind kind) {
  for (const BackendEntry &b : kBackends)
    if (b.kind == kind) return b;
  assert(false && "a BackendKind without an entry in kBackends");
  return kBackends[0];
}

} // namespace

std::span<const BackendEntry> backends() { return kBackends; }

std::string backendName(BackendKind kind) { return entry(kind).name; }

std::unique_ptr<Accelerator> makeAccelerator(BackendKind kind, const Scene &scene) {
  return entry(kind).make(scene);
}

std::unique_ptr<Accelerator> makeAccelerator(std::string_view name, const Scene &scene) {
  for (const BackendEntry &b : kBackends)
    if (name == b.name) return b.make(scene);
  throw std::invalid_argument("unknown backend '" + std::string(name) + "'");
}

} // namespace lray
