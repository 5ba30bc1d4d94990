// Pipeline: run. The render threads: woken before a frame's render, and
// each worker placed once on a CPU of its own.
#pragma once

#include <vector>

namespace lray {

/// Wakes TBB's worker threads ahead of a frame (by the time the backend's
/// build ends they are up), from the thread that will render with them.
/// The first time a worker enters, it moves once to a CPU of its own: Linux
/// starts a new thread on its creator's CPU, busy with the main thread, and
/// moves one of them to an idle CPU only at a scheduler tick (4 ms at
/// HZ=250), so a frame of a few milliseconds rendered on one CPU for most
/// of its time in about half the runs on a 2-core machine. The move sets
/// the worker's affinity to that CPU and back to every CPU it had: no
/// thread stays pinned, and Linux balances them as usual from there on.
void wakeRenderThreads();

/// The CPU the worker in arena slot `slot` (1, 2, ...) moves to: `allowed`
/// (the process's CPUs, ascending) from the main thread's `mainCpu` on,
/// `slot` places further, wrapping; -1 where `mainCpu` is not in `allowed`
/// or there is no other CPU.
int placementCpu(const std::vector<int> &allowed, int mainCpu, int slot);

/// Moves the calling thread to `cpu` (one of its affinity mask's) and
/// gives it its whole mask back. False (and nothing changed) where `cpu`
/// is not in the mask or the system refused.
bool moveToCpu(int cpu);

} // namespace lray
