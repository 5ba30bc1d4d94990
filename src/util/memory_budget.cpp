// Pipeline: shared utilities. See memory_budget.h.
#include "util/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace lray {

uint64_t defaultRenderMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  const uint64_t machine = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
  return std::max<uint64_t>(uint64_t{1} << 30, machine / 2);
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
