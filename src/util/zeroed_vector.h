// Util: a vector of numbers whose memory comes zeroed from calloc, for the
// frame-sized buffers (the film, the adaptive sample buffer). A fresh
// buffer's pages are then mapped by whichever render thread first writes
// each, in parallel with the others, not all at once by the thread that
// allocates it (a fresh page costs a fault and the zeroing of its 4 KB:
// about 0.5 ms per MB on the machine of bench/README.md's Throughput).
// Sized once: value-initialising writes nothing, so elements dropped by a
// shrinking resize and brought back by a growing one keep their values.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace lray {

template <class T> struct ZeroedAllocator {
  static_assert(std::is_arithmetic_v<T>, "all-zero bytes are the value 0 of numbers only");
  using value_type = T;

  ZeroedAllocator() = default;
  template <class U> ZeroedAllocator(const ZeroedAllocator<U> &) noexcept {}

  T *allocate(size_t n) {
    if (void *p = std::calloc(n, sizeof(T))) return static_cast<T *>(p);
    throw std::bad_alloc();
  }
  void deallocate(T *p, size_t) noexcept { std::free(p); }

  /// Value-initialising an element (vector(n), resize(n)) writes nothing:
  /// calloc's memory already holds 0.
  template <class U> void construct(U *) noexcept {}
  template <class U, class... Args> void construct(U *p, Args &&...args) {
    ::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
  }

  template <class U> bool operator==(const ZeroedAllocator<U> &) const noexcept { return true; }
};

/// Construct with the size alone (`ZeroedVector<float> v(n)`): a size and a
/// value, even 0, writes every element.
template <class T> using ZeroedVector = std::vector<T, ZeroedAllocator<T>>;

} // namespace lray
