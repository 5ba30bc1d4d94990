// Pipeline: shared utilities. See memory_budget.h.
#include "util/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

namespace lray {

uint64_t memoryAvailable() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  uint64_t bytes = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : UINT64_MAX;
  // A process limited further (ulimit -v, a container's or a Slurm job's
  // cgroup) has only that much: past it LRay would die in an allocation.
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    bytes = std::min<uint64_t>(bytes, as.rlim_cur);
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");
  std::string max;
  if (cgroup >> max && !max.empty() && max != "max") {
    try {
      bytes = std::min<uint64_t>(bytes, std::stoull(max));
    } catch (const std::exception &) {
    }
  }
  return bytes;
}

uint64_t defaultRenderMemory() {
  return std::max<uint64_t>(uint64_t{256} << 20, memoryAvailable() / 2);
}

std::string bytesText(uint64_t bytes) {
  char text[32];
  const char *units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  double value = static_cast<double>(bytes);
  while (value >= 1024 && unit < 4) {
    value /= 1024;
    ++unit;
  }
  if (unit == 0) std::snprintf(text, sizeof text, "%llu bytes", (unsigned long long)bytes);
  else if (value == static_cast<double>(static_cast<uint64_t>(value)))
    std::snprintf(text, sizeof text, "%.0f %s", value, units[unit]);
  else std::snprintf(text, sizeof text, "%.1f %s", value, units[unit]);
  return text;
}

void MemoryBudget::charge(uint64_t bytes, const std::string &what, const SourceLocation &loc) {
  // Saturating: a charge computed from absurd counts must not wrap.
  const uint64_t total = bytes > UINT64_MAX - used_ ? UINT64_MAX : used_ + bytes;
  if (limit_ != 0 && total > limit_)
    throw SceneError(loc, what + ": the frame would need more than the render memory budget of " +
                              bytesText(limit_) + " (raise it with --render-memory)");
  used_ = total;
}

} // namespace lray
