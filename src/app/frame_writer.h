// Pipeline: application. Writes an animation's frames while the next ones
// render (README.md, "The `lray` command"): encoding a PNG is one thread's
// work (zlib), and while the frame loop waited for it every other core sat
// idle. The writes are tasks among the render's own threads (no thread
// beyond --threads), each frame's file still appears atomically, and a
// failed write stops the run as before, a frame or a few later.
#pragma once

#include <tbb/task_group.h>

#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lray {

class FrameWriter {
public:
  /// The most memory the frames waiting to be written may hold: a frame
  /// bigger than this is written at once, before the next one renders.
  static constexpr size_t kMaxPendingBytes = size_t{512} << 20;

  /// `threads`: the run's render threads (with one, every write is done at
  /// once: nothing else could run beside it). `failing(path)` is called
  /// just before the failure of the write of `path` is rethrown.
  FrameWriter(int threads, std::function<void(const std::string &path)> failing);
  FrameWriter(const FrameWriter &) = delete;
  FrameWriter &operator=(const FrameWriter &) = delete;
  /// Waits for the writes still running (their failures are dropped: an
  /// exception is already on its way).
  ~FrameWriter();

  /// Writes a frame by `write` (which owns the frame, `bytes` of it) to
  /// `path`. `written(seconds)` is called on this thread once the file is
  /// complete, in the order the frames were submitted: at a later submit or
  /// at finish().
  void submit(std::string path, size_t bytes, std::function<void()> write,
              std::function<void(double seconds)> written);
  /// Waits for every write. The first failure among them (in submission
  /// order) is rethrown, after `written` for the frames before it.
  void finish();

private:
  struct Job {
    std::string path;
    std::function<void()> write;
    std::function<void(double)> written;
    std::exception_ptr error;
    double seconds = 0;
  };
  /// Writes `job` on the calling thread, catching its failure into it.
  static void run(Job &job);

  size_t maxPending_;
  std::function<void(const std::string &)> failing_;
  tbb::task_group group_;
  std::vector<std::unique_ptr<Job>> pending_;
  size_t pendingBytes_ = 0;
};

} // namespace lray
