// Pipeline: script -> scene description. See script_watchdog.h.
#include "bindings/script_watchdog.h"
#include "util/printable_text.h"

#include <cstdio>
#include <unistd.h>

namespace lray::lua {

ScriptWatchdog::~ScriptWatchdog() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ScriptWatchdog::arm(std::chrono::steady_clock::time_point deadline, std::string message) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    armed_ = true;
    ++generation_;
    deadline_ = deadline;
    message_ = std::move(message);
    if (!thread_.joinable()) thread_ = std::thread(&ScriptWatchdog::watch, this);
  }
  wake_.notify_all();
}

void ScriptWatchdog::disarm() {
  std::lock_guard<std::mutex> lock(mutex_);
  armed_ = false;
}

void ScriptWatchdog::watch() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    if (!armed_) {
      wake_.wait(lock);
      continue;
    }
    const uint64_t generation = generation_;
    const auto limit = deadline_ + kGrace;
    if (wake_.wait_until(lock, limit,
                         [&] { return stopping_ || !armed_ || generation_ != generation; }))
      continue;
    // Still in the same call, past its deadline and the grace period.
    std::fprintf(stderr, "lray: error: %s\n", printableText(message_).c_str());
    std::fflush(stderr);
    _exit(1);
  }
}

} // namespace lray::lua
