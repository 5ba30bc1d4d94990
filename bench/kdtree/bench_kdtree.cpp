// Benchmarks: the kd-tree backend on a ~1M-triangle mesh: build time,
// memory, single-ray camera-ray throughput. Usage:
//   bench_kdtree [triangles=1000000] [width=1024] [height=768]
#include "accel/kdtree/kdtree_accelerator.h"
#include "bench/kdtree/accelerator_bench.h"

#include <cstdio>
#include <cstdlib>

int main(int argc, char **argv) {
  using namespace lray;
  size_t triangles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  int width = argc > 2 ? std::atoi(argv[2]) : 1024;
  int height = argc > 3 ? std::atoi(argv[3]) : 768;

  Scene scene = bench::makeBumpySphereScene(triangles);
  KdTreeInfo info;
  bench::AcceleratorFigures fig = bench::measureAccelerator(
      scene,
      [&info](const Scene &s) {
        auto accel = std::make_unique<KdTreeAccelerator>(s);
        info = accel->meshTree(0).info();
        return accel;
      },
      width, height);
  std::printf("kdtree: %zu triangles\n", fig.stats.primitives);
  std::printf("  build           %.3f s wall (backend %.3f s), %.3f s CPU all threads\n",
              fig.wallBuildSeconds, fig.stats.buildSeconds, fig.cpuBuildSeconds);
  std::printf("  memory          %.1f MiB (tree only; mesh data %.1f MiB)\n",
              static_cast<double>(fig.stats.memoryBytes) / (1 << 20),
              static_cast<double>(scene.entities[0].mesh->memoryBytes()) / (1 << 20));
  std::printf("  mesh tree       %zu nodes, %zu leaves (%zu empty), %zu references "
              "(%zu padded), depth %d (limit %d)\n",
              info.nodes, info.leaves, info.emptyLeaves, info.primReferences,
              info.paddedReferences, info.depth, info.maxDepth);
  std::printf("  camera rays     %zu, %.1f %% hit\n", fig.rays, 100 * fig.hitFraction);
  std::printf("  intersect       %.2f Mrays/s (1 thread), %.2f Mrays/s (all threads)\n",
              fig.raysPerSecondOneThread * 1e-6, fig.raysPerSecondAllThreads * 1e-6);
  std::printf("  intersect       %.2f Mrays per CPU second (1 thread)\n",
              fig.raysPerCpuSecond * 1e-6);
  std::printf("  occluded        %.2f Mrays/s (1 thread)\n", fig.occludedPerSecondOneThread * 1e-6);
  return fig.hitFraction < 0 ? 1 : 0;
}
