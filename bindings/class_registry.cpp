// Pipeline: script -> scene description. See class_registry.h.
#include "bindings/class_registry.h"

#include <atomic>
#include <cassert>

namespace lray::lua {

int nextTypeIndex() {
  static std::atomic<int> next{0};
  return next++;
}

const ClassInfo &ClassRegistry::primary(const void *tag) const {
  auto it = primaryByType.find(tag);
  assert(it != primaryByType.end() && "type has no registered class");
  return *it->second;
}

} // namespace lray::lua
