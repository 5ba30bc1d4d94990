// Pipeline: script -> scene description. Memory that script objects hold
// outside the Lua heap (a Mesh's C++ arrays, copied from Lua tables or read
// from an OBJ), counted with the Lua heap against --script-memory: else a
// script could keep a thousand copies of one big table's mesh while its
// Lua heap stayed small.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>

namespace lray::lua {

/// The bytes held outside the Lua heap, by every charge of one script.
struct ExternalMemory {
  std::atomic<size_t> bytes{0};
};

/// What one object holds, charged to the pool for as long as it lives
/// (copies charge again: they hold their own arrays).
class MemoryCharge {
public:
  MemoryCharge() = default;
  MemoryCharge(const MemoryCharge &o) : pool_(o.pool_) { set(o.bytes_); }
  MemoryCharge &operator=(const MemoryCharge &o) {
    if (this != &o) {
      set(0);
      pool_ = o.pool_;
      set(o.bytes_);
    }
    return *this;
  }
  ~MemoryCharge() { set(0); }

  /// Charges `bytes` to `pool` from now on, in place of what was charged.
  void set(const std::shared_ptr<ExternalMemory> &pool, size_t bytes) {
    set(0);
    pool_ = pool;
    set(bytes);
  }

private:
  void set(size_t bytes) {
    if (pool_) {
      pool_->bytes += bytes;
      pool_->bytes -= bytes_;
    }
    bytes_ = bytes;
  }
  std::shared_ptr<ExternalMemory> pool_;
  size_t bytes_ = 0;
};

} // namespace lray::lua
