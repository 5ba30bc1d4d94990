// Benchmarks: backend figures over any Scene, reusable by a side-by-side
// driver (bench/backends): build time, memory, and single-ray camera-ray
// throughput through the Accelerator interface.
#pragma once

#include "accel/accelerator.h"
#include "scene/scene.h"

#include <cstddef>
#include <functional>
#include <memory>

namespace lray::bench {

/// Measured figures of one backend on one scene.
struct AcceleratorFigures {
  AcceleratorStats stats;      ///< as reported by the backend (build seconds, bytes, counts)
  double wallBuildSeconds = 0; ///< construction measured from outside
  double cpuBuildSeconds = 0;  ///< process CPU time of the construction (all threads)
  size_t rays = 0;             ///< camera rays per pass (width * height)
  double hitFraction = 0;      ///< share of camera rays that hit
  double raysPerSecondOneThread = 0;
  double raysPerCpuSecond = 0; ///< one thread, per second of that thread's CPU time
  double raysPerSecondAllThreads = 0;
  double occludedPerSecondOneThread = 0; ///< same rays as occlusion queries
};

using AcceleratorFactory = std::function<std::unique_ptr<Accelerator>(const Scene &)>;

/// Builds the backend over `scene` and traces one camera ray per pixel of a
/// width x height image from scene.camera, single rays through intersect()
/// (one thread, then all TBB threads) and occluded().
AcceleratorFigures measureAccelerator(const Scene &scene, const AcceleratorFactory &make,
                                      int width, int height);

/// A scene with one closed, bumpy sphere mesh of about `triangles`
/// triangles (radius ~1 at the origin) seen by a camera at (0, 0, -3).
Scene makeBumpySphereScene(size_t triangles);

} // namespace lray::bench
