// Pipeline: application. Frame writes overlapped with rendering
// (frame_writer.h).
#include "app/frame_writer.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace lray {

FrameWriter::FrameWriter(int threads, std::function<void(const std::string &)> failing)
    // One write for each thread beyond the first, at most four: enough to
    // keep a core per write busy where writing a frame takes longer than
    // rendering one, without holding many frames.
    : maxPending_(static_cast<size_t>(std::clamp(threads - 1, 0, 4))),
      failing_(std::move(failing)) {}

FrameWriter::~FrameWriter() {
  try {
    group_.wait();
  } catch (...) { // run() keeps every failure in its job; nothing to add
  }
}

void FrameWriter::run(Job &job) {
  const auto start = std::chrono::steady_clock::now();
  try {
    job.write();
  } catch (...) {
    job.error = std::current_exception();
  }
  job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  job.write = nullptr; // the frame goes now, not at the next finish()
}

void FrameWriter::submit(std::string path, size_t bytes, std::function<void()> write,
                         std::function<void(double)> written) {
  auto job = std::make_unique<Job>();
  job->path = std::move(path);
  job->write = std::move(write);
  job->written = std::move(written);
  if (pending_.size() >= maxPending_ || pendingBytes_ + bytes > kMaxPendingBytes) finish();
  pending_.push_back(std::move(job));
  Job &queued = *pending_.back();
  if (maxPending_ == 0 || bytes > kMaxPendingBytes) {
    run(queued); // nothing may run beside it, or it is too big to keep
    finish();
    return;
  }
  pendingBytes_ += bytes;
  group_.run([&queued] { run(queued); });
}

void FrameWriter::finish() {
  group_.wait();
  std::vector<std::unique_ptr<Job>> done;
  done.swap(pending_);
  pendingBytes_ = 0;
  for (const std::unique_ptr<Job> &job : done) {
    if (job->error) {
      failing_(job->path);
      std::rethrow_exception(job->error);
    }
    job->written(job->seconds);
  }
}

} // namespace lray
