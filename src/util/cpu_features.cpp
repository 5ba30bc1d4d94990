// Pipeline: shared utilities. cpu_features.h.
#include "util/cpu_features.h"

namespace lray {

bool cpuHasAvx2() {
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return static_cast<bool>(__builtin_cpu_supports("avx2"));
  }();
  return avx2;
}

} // namespace lray
