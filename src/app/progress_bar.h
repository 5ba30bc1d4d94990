// Pipeline: application. A one-line progress bar on a terminal; silent
// when stderr is not a terminal or with --quiet.
#pragma once

#include <cstddef>
#include <mutex>
#include <string>

namespace lray {

class ProgressBar {
public:
  /// Enabled only if `wanted` and stderr is a terminal.
  explicit ProgressBar(bool wanted);
  bool enabled() const { return enabled_; }
  /// Starts a new frame's bar with a label such as "frame 3/20".
  void start(const std::string &label);
  /// Thread-safe; redraws only when the percentage changes.
  void update(size_t done, size_t total);
  /// Ends the line.
  void finish(double seconds);

private:
  bool enabled_;
  std::mutex mutex_;
  std::string label_;
  int lastPercent_ = -1;
};

} // namespace lray
