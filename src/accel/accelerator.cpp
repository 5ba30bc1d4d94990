// Pipeline: acceleration. Backends are chosen by name at run time.
#include "accel/accelerator.h"

#include "accel/embree/embree_accelerator.h"
#include "accel/kdtree/kdtree_accelerator.h"

namespace lray {

std::string backendName(BackendKind kind) {
  return kind == BackendKind::Embree ? "embree" : "kdtree";
}

std::unique_ptr<Accelerator> makeAccelerator(BackendKind kind, const Scene &scene) {
  switch (kind) {
  case BackendKind::Embree: return std::make_unique<EmbreeAccelerator>(scene);
  case BackendKind::KdTree: return std::make_unique<KdTreeAccelerator>(scene);
  }
  return nullptr;
}

} // namespace lray
