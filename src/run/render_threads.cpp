// Pipeline: run. See render_threads.h.
#include "run/render_threads.h"

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <algorithm>
#include <atomic>

#include <sched.h>

namespace lray {

namespace {

std::vector<int> cpusOf(const cpu_set_t &set) {
  std::vector<int> cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &set)) cpus.push_back(cpu);
  return cpus;
}

/// Moves each worker, on its first entry into an arena, to its CPU
/// (placementCpu), away from the CPU the main thread had when it woke them.
class WorkerPlacement final : public tbb::task_scheduler_observer {
public:
  WorkerPlacement() { observe(true); }
  void noteMainCpu() { mainCpu_.store(sched_getcpu(), std::memory_order_relaxed); }

  void on_scheduler_entry(bool worker) override {
    static thread_local bool placed = false;
    if (!worker || placed) return;
    placed = true;
    cpu_set_t all;
    CPU_ZERO(&all);
    if (sched_getaffinity(0, sizeof all, &all) != 0) return;
    const int target = placementCpu(cpusOf(all), mainCpu_.load(std::memory_order_relaxed),
                                    tbb::this_task_arena::current_thread_index());
    if (target >= 0 && target != sched_getcpu()) moveToCpu(target);
  }

private:
  std::atomic<int> mainCpu_{-1};
};

} // namespace

bool moveToCpu(int cpu) {
  cpu_set_t all, one;
  CPU_ZERO(&all);
  CPU_ZERO(&one);
  if (cpu < 0 || cpu >= CPU_SETSIZE || sched_getaffinity(0, sizeof all, &all) != 0 ||
      !CPU_ISSET(cpu, &all))
    return false;
  CPU_SET(cpu, &one);
  // A mask without the current CPU moves the thread before the call
  // returns; the whole mask back leaves it there, unpinned.
  if (sched_setaffinity(0, sizeof one, &one) != 0) return false;
  return sched_setaffinity(0, sizeof all, &all) == 0;
}

int placementCpu(const std::vector<int> &allowed, int mainCpu, int slot) {
  const auto main = std::find(allowed.begin(), allowed.end(), mainCpu);
  if (main == allowed.end() || allowed.size() < 2 || slot < 1) return -1;
  const size_t n = allowed.size();
  return allowed[(static_cast<size_t>(main - allowed.begin()) + static_cast<size_t>(slot)) % n];
}

void wakeRenderThreads() {
  // Never destroyed: TBB may outlive static destruction's order.
  static WorkerPlacement &placement = *new WorkerPlacement;
  placement.noteMainCpu();
  tbb::this_task_arena::enqueue([] {});
}

} // namespace lray
