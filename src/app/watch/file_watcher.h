// Pipeline: application (live preview). Tells when a scene's files change
// on disk: inotify on the folders that hold them (editors often save by
// renaming a new file over the old one, which a watch on the file itself
// would miss), filtered by name, debounced.
#pragma once

#include <chrono>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace lray {

class FileWatcher {
public:
  FileWatcher();
  ~FileWatcher();
  FileWatcher(const FileWatcher &) = delete;
  FileWatcher &operator=(const FileWatcher &) = delete;

  /// Watches exactly these files from now on (paths as given, made absolute).
  void watch(const std::vector<std::string> &files);

  /// Waits up to `timeout` for a change to a watched file (written,
  /// replaced, created or deleted); after the first one, goes on reading
  /// until `quiet` passes without another (a save that touches the file
  /// several times is one change). True when something changed.
  bool waitForChange(std::chrono::milliseconds timeout, std::chrono::milliseconds quiet);

  const std::set<std::string> &files() const { return files_; }

private:
  /// Reads the pending events; true if one concerns a watched file.
  bool drain();

  int fd_ = -1;
  std::map<int, std::string> folders_; ///< watch descriptor -> folder
  std::set<std::string> files_;
};

} // namespace lray
