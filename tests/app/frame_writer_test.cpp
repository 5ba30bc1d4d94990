// FrameWriter (app/frame_writer.h): frames written beside the render, each
// one's completion reported in order, at most a few kept waiting, and a
// failed write rethrown naming its file.
#include "app/frame_writer.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace lray {
namespace {

struct Log {
  std::vector<std::string> written, failing;
};

std::function<void(double)> note(Log &log, const std::string &path) {
  return [&log, path](double seconds) {
    EXPECT_GE(seconds, 0);
    log.written.push_back(path);
  };
}

TEST(FrameWriter, ReportsEveryFrameInOrderAfterItsWriteRan) {
  Log log;
  std::atomic<int> ran{0};
  {
    FrameWriter writer(3, [&log](const std::string &p) { log.failing.push_back(p); });
    for (int i = 0; i < 7; ++i) {
      const std::string path = "f" + std::to_string(i);
      writer.submit(path, 100, [&ran] { ++ran; }, [&, path](double) {
        EXPECT_GE(ran.load(), std::stoi(path.substr(1)) + 1);
        log.written.push_back(path);
      });
      // Two frames at most wait beside the render (3 threads): the third
      // submit reported the first two.
      EXPECT_GE(log.written.size() + 2, static_cast<size_t>(i) + 1) << i;
    }
    writer.finish();
  }
  EXPECT_EQ(ran.load(), 7);
  EXPECT_EQ(log.written, (std::vector<std::string>{"f0", "f1", "f2", "f3", "f4", "f5", "f6"}));
  EXPECT_TRUE(log.failing.empty());
}

TEST(FrameWriter, OneThreadOrAFrameTooBigIsWrittenBeforeSubmitReturns) {
  Log log;
  FrameWriter single(1, [&log](const std::string &p) { log.failing.push_back(p); });
  single.submit("a", 100, [] {}, note(log, "a"));
  EXPECT_EQ(log.written, std::vector<std::string>{"a"});

  FrameWriter wide(4, [&log](const std::string &p) { log.failing.push_back(p); });
  wide.submit("b", FrameWriter::kMaxPendingBytes + 1, [] {}, note(log, "b"));
  EXPECT_EQ(log.written, (std::vector<std::string>{"a", "b"}));
  // Frames that together pass the limit: the earlier ones are finished first.
  wide.submit("c", FrameWriter::kMaxPendingBytes / 2 + 1, [] {}, note(log, "c"));
  wide.submit("d", FrameWriter::kMaxPendingBytes / 2 + 1, [] {}, note(log, "d"));
  EXPECT_EQ(log.written, (std::vector<std::string>{"a", "b", "c"}));
  wide.finish();
  EXPECT_EQ(log.written, (std::vector<std::string>{"a", "b", "c", "d"}));
}

TEST(FrameWriter, AFailedWriteIsRethrownAfterTheFramesBeforeItNamingItsFile) {
  for (int threads : {1, 2, 5}) {
    Log log;
    std::atomic<int> ran{0};
    FrameWriter writer(threads, [&log](const std::string &p) { log.failing.push_back(p); });
    bool thrown = false;
    try {
      for (int i = 0; i < 6; ++i) {
        const std::string path = "f" + std::to_string(i);
        writer.submit(
            path, 100,
            [&ran, i] {
              ++ran;
              if (i == 2) throw std::runtime_error("disk full");
            },
            note(log, path));
      }
      writer.finish();
    } catch (const std::runtime_error &e) {
      thrown = true;
      EXPECT_STREQ(e.what(), "disk full");
    }
    EXPECT_TRUE(thrown) << threads;
    EXPECT_EQ(log.written, (std::vector<std::string>{"f0", "f1"})) << threads;
    EXPECT_EQ(log.failing, std::vector<std::string>{"f2"}) << threads;
    // Not every later frame was submitted: the failure stopped the loop
    // within the frames that may wait (at most four beyond it).
    EXPECT_LE(ran.load(), 2 + 1 + 4) << threads;
  }
}

TEST(FrameWriter, WritesRunBesideTheCallerWithMoreThanOneThread) {
  if (tbb::info::default_concurrency() < 2) GTEST_SKIP() << "one core: no thread to write on";
  tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  Log log;
  std::atomic<bool> started{false};
  std::thread::id writerThread;
  FrameWriter writer(2, [&log](const std::string &p) { log.failing.push_back(p); });
  writer.submit(
      "bg", 100,
      [&] {
        writerThread = std::this_thread::get_id();
        started = true;
      },
      note(log, "bg"));
  // The write starts while the caller goes on (here: waits up to 10 s).
  for (int i = 0; i < 10000 && !started; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(started.load());
  EXPECT_TRUE(log.written.empty()); // reported at finish, not before
  writer.finish();
  EXPECT_NE(writerThread, std::this_thread::get_id());
  EXPECT_EQ(log.written, std::vector<std::string>{"bg"});
}

} // namespace
} // namespace lray
