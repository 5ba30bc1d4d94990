// Pipeline: application (live preview). See file_watcher.h.
#include "app/watch/file_watcher.h"

#include "util/scene_error.h"

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace lray {

namespace fs = std::filesystem;

namespace {

constexpr uint32_t kEvents = IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE | IN_DELETE;

std::string absolute(const std::string &path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  return (ec ? fs::path(path) : p).lexically_normal().string();
}

} // namespace

FileWatcher::FileWatcher() : fd_(inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
  if (fd_ < 0)
    throw SceneError(std::string("--watch: cannot watch files (inotify: ") + std::strerror(errno) +
                     ")");
}

FileWatcher::~FileWatcher() { close(fd_); }

void FileWatcher::watch(const std::vector<std::string> &files) {
  std::set<std::string> next, folders;
  for (const std::string &f : files) {
    next.insert(absolute(f));
    folders.insert(fs::path(absolute(f)).parent_path().string());
  }
  for (auto it = folders_.begin(); it != folders_.end();) {
    if (!folders.count(it->second)) {
      inotify_rm_watch(fd_, it->first);
      it = folders_.erase(it);
    } else {
      folders.erase(it->second); // already watched
      ++it;
    }
  }
  for (const std::string &folder : folders) {
    int wd = inotify_add_watch(fd_, folder.c_str(), kEvents);
    if (wd >= 0) folders_[wd] = folder;
  }
  files_ = std::move(next);
}

bool FileWatcher::drain() {
  bool changed = false;
  alignas(inotify_event) char buffer[8192];
  for (;;) {
    ssize_t n = read(fd_, buffer, sizeof buffer);
    if (n <= 0) break;
    for (char *p = buffer; p < buffer + n;) {
      const auto *e = reinterpret_cast<const inotify_event *>(p);
      if (e->mask & IN_Q_OVERFLOW) changed = true; // events were lost: assume ours
      if (e->mask & IN_IGNORED) { // the folder went away: watch() adds it again
        folders_.erase(e->wd);
        p += sizeof(inotify_event) + e->len;
        changed = true;
        continue;
      }
      auto folder = folders_.find(e->wd);
      if (folder != folders_.end() && e->len > 0 &&
          files_.count((fs::path(folder->second) / e->name).string()))
        changed = true;
      p += sizeof(inotify_event) + e->len;
    }
  }
  return changed;
}

bool FileWatcher::waitForChange(std::chrono::milliseconds timeout,
                                std::chrono::milliseconds quiet) {
  pollfd p{fd_, POLLIN, 0};
  auto waitFor = [&](std::chrono::milliseconds ms) {
    return poll(&p, 1, static_cast<int>(ms.count())) > 0;
  };
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool changed = false;
  while (!changed) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || !waitFor(left)) return false;
    changed = drain();
  }
  // Debounce: wait for `quiet` without an event.
  while (waitFor(quiet)) drain();
  return true;
}

} // namespace lray
