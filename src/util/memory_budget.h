// Pipeline: shared utilities. The render side's memory budget
// (--render-memory, README.md "Security"): what one frame's scene model,
// texture images and acceleration structure may take, charged before each
// is allocated, so that a scene asking for more is refused at the line (or
// file) that asked, naming the option, instead of running the machine out
// of memory. The script's own memory is --script-memory's.
#pragma once

#include "util/scene_error.h"

#include <cstdint>
#include <string>

namespace lray {

/// The memory this process may have: the machine's, or less under an
/// address-space limit (ulimit -v) or a cgroup's memory.max.
uint64_t memoryAvailable();

/// Half of memoryAvailable(), at least 256 MiB: the default budget (the
/// script's own memory, --script-memory, and LRay's code are the rest).
uint64_t defaultRenderMemory();

/// "512 MiB", "2 GiB", "3.2 GiB": a size for a message.
std::string bytesText(uint64_t bytes);

class MemoryBudget {
public:
  /// `limit` bytes in all (0: no limit), `used` of them already charged.
  explicit MemoryBudget(uint64_t limit = 0, uint64_t used = 0) : limit_(limit), used_(used) {}

  /// Charges `bytes` for `what` ("Sphere", "texture 'wood.png'"); past the
  /// limit throws SceneError at `loc`: "what: the frame would need more
  /// than the render memory budget of 2 GiB (raise it with --render-memory)".
  void charge(uint64_t bytes, const std::string &what, const SourceLocation &loc = {});

  /// Gives back what a finished step no longer holds (a decoder's buffer).
  void release(uint64_t bytes) { used_ -= bytes < used_ ? bytes : used_; }

  uint64_t used() const { return used_; }
  uint64_t limit() const { return limit_; }

private:
  uint64_t limit_, used_;
};

} // namespace lray
