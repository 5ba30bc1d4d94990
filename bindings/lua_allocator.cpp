// Pipeline: script -> scene description. See lua_allocator.h.
#include "bindings/lua_allocator.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <sys/mman.h>

namespace lray::lua {

std::string LuaAllocator::formatBytes(size_t bytes) {
  char text[32];
  if (bytes >= (size_t{1} << 30) && bytes % (size_t{1} << 30) == 0)
    std::snprintf(text, sizeof text, "%zu GiB", bytes >> 30);
  else if (bytes >= (size_t{1} << 20) && bytes % (size_t{1} << 20) == 0)
    std::snprintf(text, sizeof text, "%zu MiB", bytes >> 20);
  else if (bytes >= (size_t{1} << 10) && bytes % (size_t{1} << 10) == 0)
    std::snprintf(text, sizeof text, "%zu KiB", bytes >> 10);
  else
    std::snprintf(text, sizeof text, "%zu bytes", bytes);
  return text;
}

std::string LuaAllocator::limitMessage() const {
  return "the script needed more than " + formatBytes(limit_) +
         " of memory and was stopped (raise the limit with --script-memory)";
}

LuaAllocator::~LuaAllocator() {
  for (void *slab : slabs_) std::free(slab);
}

void *LuaAllocator::allocSmall(size_t cls) {
  if (FreeBlock *b = free_[cls]) {
    free_[cls] = b->next;
    return b;
  }
  size_t bytes = (cls + 1) * kGranule;
  if (static_cast<size_t>(bumpEnd_ - bump_) < bytes) {
    // The tail of the old slab is left unused (at most kMaxSmall bytes).
    // The first slab is small: a short script then touches a few ordinary
    // pages instead of having the kernel clear a 2 MiB huge page (a large
    // share of a tiny script's run time: bench/HISTORY.md). Later slabs are
    // 2 MiB-aligned and can be backed by transparent huge pages: one page
    // fault per slab instead of 512 while a big scene grows.
    bool first = slabs_.empty();
    size_t slabBytes = first ? kFirstSlabBytes : kSlabBytes;
    void *slab = std::aligned_alloc(first ? 4096 : kSlabBytes, slabBytes);
    if (!slab) return nullptr;
#ifdef MADV_HUGEPAGE
    if (!first) madvise(slab, slabBytes, MADV_HUGEPAGE);
#endif
    slabs_.push_back(slab);
    bump_ = static_cast<char *>(slab);
    bumpEnd_ = bump_ + slabBytes;
  }
  void *p = bump_;
  bump_ += bytes;
  return p;
}

void LuaAllocator::freeSmall(void *p, size_t cls) {
  auto *b = static_cast<FreeBlock *>(p);
  b->next = free_[cls];
  free_[cls] = b;
}

void *LuaAllocator::allocate(void *ud, void *ptr, size_t oldSize, size_t newSize) {
  auto &self = *static_cast<LuaAllocator *>(ud);
  // Lua passes the block's true size as oldSize when ptr is not null; when
  // ptr is null oldSize only tells the object kind.
  if (!ptr) oldSize = 0;
  bool oldSmall = ptr && oldSize <= kMaxSmall;
  bool newSmall = newSize > 0 && newSize <= kMaxSmall;
  if (newSize == 0) {
    if (ptr) {
      if (oldSmall)
        self.freeSmall(ptr, sizeClass(oldSize));
      else
        std::free(ptr);
      self.inUse_ -= oldSize;
    }
    return nullptr;
  }
  if (self.limit_ && newSize > oldSize && !self.deferred_) {
    // Compared as room left, so a request near SIZE_MAX cannot wrap around.
    const size_t held = self.inUse_ + self.external_->bytes.load(std::memory_order_relaxed);
    if (held >= self.limit_ || newSize - oldSize > self.limit_ - held) {
      self.refused_ = true;
      return nullptr;
    }
  }
  if (ptr && oldSmall && newSmall && sizeClass(oldSize) == sizeClass(newSize)) {
    self.inUse_ += newSize - oldSize;
    return ptr;
  }
  if (ptr && !oldSmall && !newSmall) {
    void *p = std::realloc(ptr, newSize);
    if (p) self.inUse_ += newSize - oldSize;
    return p;
  }
  void *p = newSmall ? self.allocSmall(sizeClass(newSize)) : std::malloc(newSize);
  if (!p) return nullptr;
  if (ptr) {
    std::memcpy(p, ptr, oldSize < newSize ? oldSize : newSize);
    if (oldSmall)
      self.freeSmall(ptr, sizeClass(oldSize));
    else
      std::free(ptr);
  }
  self.inUse_ += newSize - oldSize;
  return p;
}

} // namespace lray::lua
