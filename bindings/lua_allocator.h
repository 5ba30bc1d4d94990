// Pipeline: script -> scene description. The Lua state's memory allocator:
// small blocks (the userdata, tables and strings a scene script makes by the
// million) come from per-size free lists carved out of large slabs, which is
// several times faster than malloc for this pattern and does not fragment.
#pragma once

#include "bindings/external_memory.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace lray::lua {

class LuaAllocator {
public:
  LuaAllocator() = default;
  ~LuaAllocator();
  LuaAllocator(const LuaAllocator &) = delete;
  LuaAllocator &operator=(const LuaAllocator &) = delete;

  /// lua_Alloc: `ud` is the LuaAllocator.
  static void *allocate(void *ud, void *ptr, size_t oldSize, size_t newSize);

  /// Bytes currently handed out to Lua.
  size_t bytesInUse() const { return inUse_; }

  /// Refuse any growth past `bytes` in use (0: no limit): Lua then raises a
  /// memory error (--script-memory). Shrinking never fails.
  void setLimit(size_t bytes) { limit_ = bytes; }
  size_t limit() const { return limit_; }
  /// The memory script objects hold outside the Lua heap: it counts
  /// against the limit too.
  const std::shared_ptr<ExternalMemory> &external() const { return external_; }
  /// Whether the Lua heap and the external memory together are past the limit.
  bool overLimit() const { return limit_ && inUse_ + external_->bytes.load() > limit_; }
  /// "the script needed more than <limit> of memory and was stopped (...)":
  /// the one message for a script past the limit, whoever noticed it.
  std::string limitMessage() const;
  /// "2 GiB", "512 KiB", "1000 bytes": a size as the user would write it.
  static std::string formatBytes(size_t bytes);
  /// While deferred (nests), growth past the limit is granted, not refused:
  /// see DeferredMemoryLimit in lua_binding.h.
  void deferLimit() { ++deferred_; }
  void restoreLimit() { deferred_ -= deferred_ > 0; }
  /// Ends every deferral (one left open by a longjmp).
  void clearDeferrals() { deferred_ = 0; }
  /// Whether a request was refused since the last call (and clears it).
  bool takeRefused() {
    bool r = refused_;
    refused_ = false;
    return r;
  }

private:
  static constexpr size_t kGranule = 16;
  static constexpr size_t kMaxSmall = 512;
  static constexpr size_t kClasses = kMaxSmall / kGranule;
  static constexpr size_t kSlabBytes = 2 * 1024 * 1024;
  static constexpr size_t kFirstSlabBytes = 128 * 1024;

  static size_t sizeClass(size_t size) { return (size + kGranule - 1) / kGranule - 1; }
  void *allocSmall(size_t cls);
  void freeSmall(void *p, size_t cls);

  struct FreeBlock {
    FreeBlock *next;
  };
  FreeBlock *free_[kClasses] = {};
  char *bump_ = nullptr;    ///< next unused byte of the current slab
  char *bumpEnd_ = nullptr;
  std::vector<void *> slabs_;
  size_t inUse_ = 0;
  size_t limit_ = 0;
  bool refused_ = false;
  int deferred_ = 0;
  std::shared_ptr<ExternalMemory> external_ = std::make_shared<ExternalMemory>();
};

} // namespace lray::lua
