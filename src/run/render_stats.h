// Pipeline: run. What --stats FILE reports, as JSON.
#pragma once

#include "accel/accelerator.h"
#include "render/film.h"
#include "render/frame_settings.h"
#include "shading/ray_counts.h"

#include <chrono>
#include <string>
#include <vector>

namespace lray {

/// Figures for one rendered frame. Times in seconds.
struct FrameStats {
  int frame = 0;
  double clock = 0;
  std::string file;
  double sceneSeconds = 0; ///< scene(clock) + conversion to the scene model
  /// How many times scene(clock) ran for the frame: its motion steps with
  /// motion blur (lua/README.md, "Motion blur"), else 1.
  int sceneCalls = 1;
  double imageSeconds = 0;  ///< loading texture images not yet cached
  double renderSeconds = 0; ///< tiles: tracing and shading
  double writeSeconds = 0;
  AcceleratorStats accel;
  size_t entities = 0, lights = 0;
  std::vector<std::string> warnings; ///< e.g. the camera-aspect warning
  RayCounts rays;
  SamplingReport sampling;
};

/// The whole run.
struct RunStats {
  std::string scene;
  std::string backend;
  int threads = 0;
  int width = 0, height = 0, samples = 0;
  FrameSettings sampling; ///< the adaptive and light-sampling choices
  std::string settings;   ///< the run plan's settings as JSON (RunPlan::settingsJson)
  double loadSeconds = 0; ///< running the script file itself
  double totalSeconds = 0;
  size_t peakMemoryBytes = 0;
  std::vector<FrameStats> frames;
};

std::string toJson(const RunStats &stats);

/// Wall-clock seconds since `t0` (the unit of every time in these stats).
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Peak resident set size of this process so far.
size_t peakMemoryBytes();

} // namespace lray
