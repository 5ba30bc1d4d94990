// Pipeline: run. JSON for --stats (flat, hand-written: no JSON
// library needed for numbers and a few escaped strings).
#include "run/render_stats.h"

#include "util/json_string.h"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>

namespace lray {

namespace {

std::string raysJson(const RayCounts &r) {
  return fmt::format(
      R"({{"camera": {}, "shadow": {}, "shadow_skipped": {}, "reflection": {}, )"
      R"("refraction": {}, "diffuse": {}, "total": {}, "paths": {}, "mean_path_length": {:.6g}}})",
      r.camera, r.shadow, r.shadowSkipped, r.reflection, r.refraction, r.diffuse,
      r.camera + r.shadow + r.reflection + r.refraction + r.diffuse, r.paths,
      r.paths ? static_cast<double>(r.pathVertices) / static_cast<double>(r.paths) : 0.0);
}

std::string errorJson(bool has, double value) {
  return has ? fmt::format("{:.6g}", value) : std::string("null");
}

std::string frameSamplingJson(const FrameStats &f, int width, int height) {
  const SamplingReport &r = f.sampling;
  const double pixels = static_cast<double>(width) * height;
  return fmt::format(
      R"({{"passes": {}, "samples": {}, "samples_per_pixel": {:.6g}, "max_pixel_samples": {}, )"
      R"("error_mean": {}, "error_max": {}, "time_limit_hit": {}}})",
      r.passes, r.samples, pixels > 0 ? static_cast<double>(r.samples) / pixels : 0,
      r.maxPixelSamples, errorJson(r.hasError, r.meanError), errorJson(r.hasError, r.maxError),
      r.timeLimitHit ? "true" : "false");
}

} // namespace

std::string toJson(const RunStats &s) {
  RayCounts total;
  double build = 0, render = 0, sceneT = 0, write = 0, images = 0;
  uint64_t nonFinite = 0, samples = 0;
  double errorSum = 0, errorMax = 0;
  size_t withError = 0;
  for (const FrameStats &f : s.frames) {
    samples += f.sampling.samples;
    if (f.sampling.hasError) {
      errorSum += f.sampling.meanError;
      errorMax = std::max(errorMax, f.sampling.maxError);
      ++withError;
    }
    total += f.rays;
    build += f.accel.buildSeconds;
    render += f.renderSeconds;
    sceneT += f.sceneSeconds;
    write += f.writeSeconds;
    images += f.imageSeconds;
    nonFinite += f.rays.nonFinite;
  }
  std::string out = "{\n";
  out += fmt::format("  \"lray_version\": {},\n", jsonString(LRAY_VERSION));
  out += fmt::format("  \"scene\": {},\n  \"backend\": {},\n", jsonString(s.scene),
                     jsonString(s.backend));
  out +=
      fmt::format("  \"threads\": {},\n  \"width\": {},\n  \"height\": {},\n  \"samples\": {},\n",
                  s.threads, s.width, s.height, s.samples);
  out += fmt::format(
      "  \"times\": {{\"load_script\": {:.6f}, \"scene\": {:.6f}, \"images\": {:.6f}, "
      "\"build\": {:.6f}, \"render\": {:.6f}, \"write\": {:.6f}, \"total\": {:.6f}}},\n",
      s.loadSeconds, sceneT, images, build, render, write, s.totalSeconds);
  const AdaptiveSettings &a = s.sampling.adaptiveSettings;
  out += fmt::format(
      "  \"sampling\": {{\"mode\": \"{}\", \"light_sampling\": \"{}\", \"noise_threshold\": "
      "{:.6g}, "
      "\"min_samples\": {}, \"max_samples\": {}, \"edge_lattice\": {}, \"sparse_centres\": {}, "
      "\"time_limit\": {:.6g}, "
      "\"seed\": {}}},\n",
      s.sampling.adaptive ? "adaptive" : "fixed",
      s.sampling.lightSampling == LightSampling::Spread ? "spread" : "all",
      s.sampling.adaptive ? a.noiseThreshold : 0.0, s.sampling.adaptive ? a.minSamples : 0,
      s.sampling.adaptive ? a.maxSamples : 0, s.sampling.adaptive ? a.latticeDepth : 0,
      s.sampling.adaptive && a.sparseCentres,
      s.sampling.adaptive ? a.timeLimit : 0.0, s.sampling.seed);
  if (!s.settings.empty()) out += fmt::format("  \"settings\": {},\n", s.settings);
  const double pixels =
      static_cast<double>(s.width) * s.height * static_cast<double>(s.frames.size());
  out += fmt::format("  \"camera_samples\": {},\n  \"samples_per_pixel\": {:.6g},\n", samples,
                     pixels > 0 ? static_cast<double>(samples) / pixels : 0);
  out += fmt::format(
      "  \"error\": {{\"mean\": {}, \"max\": {}}},\n",
      errorJson(withError > 0, withError ? errorSum / static_cast<double>(withError) : 0),
      errorJson(withError > 0, errorMax));
  out += fmt::format("  \"rays\": {},\n", raysJson(total));
  out += fmt::format("  \"non_finite_samples\": {},\n", nonFinite);
  out += fmt::format("  \"peak_memory_bytes\": {},\n", s.peakMemoryBytes);
  out += "  \"frames\": [";
  for (size_t i = 0; i < s.frames.size(); ++i) {
    const FrameStats &f = s.frames[i];
    out += i ? ",\n    " : "\n    ";
    out +=
        fmt::format(R"({{"frame": {}, "clock": {}, "scene_calls": {}, "file": {}, "entities": {}, )"
                    R"("lights": {}, )"
                    R"("primitives": {}, "instances": {}, )"
                    R"("accel_memory_bytes": {}, "times": {{"scene": {:.6f}, "images": {:.6f}, )"
                    R"("build": {:.6f}, "render": {:.6f}, "write": {:.6f}}}, )"
                    R"("rays": {}, "non_finite_samples": {}, "sampling": {}}})",
                    f.frame, f.clock, f.sceneCalls, jsonString(f.file), f.entities, f.lights,
                    f.accel.primitives, f.accel.instances, f.accel.memoryBytes, f.sceneSeconds,
                    f.imageSeconds, f.accel.buildSeconds, f.renderSeconds, f.writeSeconds,
                    raysJson(f.rays), f.rays.nonFinite, frameSamplingJson(f, s.width, s.height));
  }
  out += s.frames.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

size_t peakMemoryBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<size_t>(usage.ru_maxrss) * 1024;
}

} // namespace lray
