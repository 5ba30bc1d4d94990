// Pipeline: script -> scene description. The last line of defence of
// --script-timeout: the instruction hook stops a script's own loops, but
// not one long call into the C library (a pattern search that backtracks
// for days, a huge string.rep), which never returns to the hook. A thread
// waits for each script call's deadline plus a grace period; if the call
// is still running then, it prints the error naming the scene and ends the
// process (exit status 1). No image is being written while a script runs,
// so nothing half-written is left under a final name.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace lray::lua {

class ScriptWatchdog {
public:
  /// The hook gets this long past the deadline before the watchdog acts.
  static constexpr std::chrono::milliseconds kGrace{2000};

  ScriptWatchdog() = default;
  ~ScriptWatchdog();
  ScriptWatchdog(const ScriptWatchdog &) = delete;
  ScriptWatchdog &operator=(const ScriptWatchdog &) = delete;

  /// Watches the call starting now: after `deadline` + kGrace the process
  /// ends with "lray: error: <message>".
  void arm(std::chrono::steady_clock::time_point deadline, std::string message);
  /// The call returned in time.
  void disarm();

private:
  void watch();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
  bool armed_ = false, stopping_ = false;
  uint64_t generation_ = 0;
  std::chrono::steady_clock::time_point deadline_;
  std::string message_;
};

} // namespace lray::lua
