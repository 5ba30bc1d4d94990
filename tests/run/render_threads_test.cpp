// Tests for run/render_threads: where a worker moves on its first entry,
// and that it is not left pinned there.
#include "run/render_threads.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <thread>

#include <elf.h>
#include <sched.h>

namespace lray {
namespace {

TEST(RenderThreads, EachWorkerTakesTheCpuItsSlotPlacesFromTheMainThreads) {
  const std::vector<int> cpus{0, 1, 2, 3};
  EXPECT_EQ(placementCpu(cpus, 0, 1), 1);
  EXPECT_EQ(placementCpu(cpus, 2, 1), 3);
  EXPECT_EQ(placementCpu(cpus, 2, 2), 0); // wraps
  EXPECT_EQ(placementCpu(cpus, 3, 3), 2);
  // A process limited to some CPUs (taskset) places among those alone.
  EXPECT_EQ(placementCpu({2, 5, 7}, 7, 1), 2);
  EXPECT_EQ(placementCpu({2, 5, 7}, 2, 1), 5);
}

TEST(RenderThreads, NoPlaceWithoutAnotherCpuOrTheMainThreadsCpu) {
  EXPECT_EQ(placementCpu({3}, 3, 1), -1);        // one CPU: nowhere to go
  EXPECT_EQ(placementCpu({0, 1}, 4, 1), -1);     // main thread outside the mask
  EXPECT_EQ(placementCpu({0, 1}, -1, 1), -1);    // sched_getcpu failed
  EXPECT_EQ(placementCpu({0, 1}, 0, 0), -1);     // slot 0 is the main thread's
  EXPECT_EQ(placementCpu({0, 1}, 0, -1), -1);    // not in an arena
}

bool sameMask(const cpu_set_t &a, const cpu_set_t &b) { return CPU_EQUAL(&a, &b) != 0; }

TEST(RenderThreads, AMovedThreadGetsItsWholeMaskBack) {
  cpu_set_t before, after;
  CPU_ZERO(&before);
  CPU_ZERO(&after);
  ASSERT_EQ(sched_getaffinity(0, sizeof before, &before), 0);
  int last = -1;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &before)) last = cpu;
  ASSERT_TRUE(moveToCpu(last));
  ASSERT_EQ(sched_getaffinity(0, sizeof after, &after), 0);
  EXPECT_TRUE(sameMask(before, after));
  // A CPU outside the mask, or none: nothing changes.
  EXPECT_FALSE(moveToCpu(CPU_SETSIZE));
  EXPECT_FALSE(moveToCpu(-1));
  if (last + 1 < CPU_SETSIZE) {
    EXPECT_FALSE(moveToCpu(last + 1));
  }
  ASSERT_EQ(sched_getaffinity(0, sizeof after, &after), 0);
  EXPECT_TRUE(sameMask(before, after));
}

TEST(RenderThreads, AWorkerIsMovedOnceAndLeftFreeToRunOnEveryCpu) {
  cpu_set_t process;
  CPU_ZERO(&process);
  ASSERT_EQ(sched_getaffinity(0, sizeof process, &process), 0);
  if (CPU_COUNT(&process) < 2) GTEST_SKIP() << "one CPU: no worker is moved";
  tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  wakeRenderThreads();
  // Iterations that each wait (up to 10 s) for a worker to have run one:
  // the worker records its mask on the way.
  std::atomic<bool> workerRan{false}, workerUnpinned{false};
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  tbb::parallel_for(0, 64, [&](int) {
    if (tbb::this_task_arena::current_thread_index() > 0 && !workerRan) {
      cpu_set_t mine;
      CPU_ZERO(&mine);
      workerUnpinned = sched_getaffinity(0, sizeof mine, &mine) == 0 && sameMask(mine, process);
      workerRan = true;
    }
    while (!workerRan && std::chrono::steady_clock::now() < until)
      std::this_thread::yield();
  });
  ASSERT_TRUE(workerRan) << "no worker joined the loop in 10 s";
  EXPECT_TRUE(workerUnpinned) << "the worker's affinity is not the process's";
}

/// The size in memory of `path`'s thread-local block (its PT_TLS
/// segment), or -1 where the file is no 64-bit ELF or has none.
int64_t threadLocalBlockBytes(const char *path) {
  std::ifstream in(path, std::ios::binary);
  Elf64_Ehdr header{};
  if (!in.read(reinterpret_cast<char *>(&header), sizeof header) ||
      header.e_ident[EI_CLASS] != ELFCLASS64 || header.e_phentsize != sizeof(Elf64_Phdr))
    return -1;
  for (int i = 0; i < header.e_phnum; ++i) {
    Elf64_Phdr segment{};
    in.seekg(static_cast<std::streamoff>(header.e_phoff + i * sizeof segment));
    if (!in.read(reinterpret_cast<char *>(&segment), sizeof segment)) return -1;
    if (segment.p_type == PT_TLS) return static_cast<int64_t>(segment.p_memsz);
  }
  return -1;
}

// glibc copies and zeroes a program's thread-local block for every thread
// it starts (TBB's workers, the script watchdog), rendering or not, on
// the thread that starts it: halving lray's, 1.65 to 0.82 MB, took 2-3 ms
// off a 1x1 render's wall time, and one set of tile arrays for every
// backend and integrator (0.82 to 0.30 MB) more (bench/README.md,
// "Start-up"). Big per-thread arrays belong on the heap or shared by
// their users: a copy per template instance is zeroed for every thread.
TEST(RenderThreads, LraysThreadLocalBlockStaysUnderHalfAMebibyte) {
  const int64_t bytes = threadLocalBlockBytes(LRAY_BINARY);
  ASSERT_GT(bytes, 0) << LRAY_BINARY << ": no thread-local block found";
  EXPECT_LT(bytes, int64_t{1} << 19);
}

} // namespace
} // namespace lray
