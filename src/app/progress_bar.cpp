// Pipeline: application. Terminal progress bar.
#include "app/progress_bar.h"

#include <cstdio>
#include <unistd.h>

namespace lray {

ProgressBar::ProgressBar(bool wanted) : enabled_(wanted && isatty(fileno(stderr))) {}

void ProgressBar::start(const std::string &label) {
  std::lock_guard<std::mutex> lock(mutex_);
  label_ = label;
  lastPercent_ = -1;
}

void ProgressBar::update(size_t done, size_t total) {
  if (!enabled_ || total == 0) return;
  int percent = static_cast<int>(done * 100 / total);
  std::lock_guard<std::mutex> lock(mutex_);
  if (percent <= lastPercent_) return;
  lastPercent_ = percent;
  constexpr int kWidth = 40;
  int filled = percent * kWidth / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled,
               "########################################", kWidth - filled, "", percent);
  std::fflush(stderr);
}

void ProgressBar::finish(double seconds) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  std::fprintf(stderr, "\r%s done in %.2f s%*s\n", label_.c_str(), seconds, 40, "");
  std::fflush(stderr);
}

} // namespace lray
