// Pipeline: application. JSON for --stats (flat, hand-written: no JSON
// library needed for numbers and a few escaped strings).
#include "app/render_stats.h"

#include <fmt/format.h>
#include <sys/resource.h>

namespace lray {

namespace {

std::string quoted(const std::string &s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\t': out += "\\t"; break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", c);
      else out += c;
    }
  }
  return out + "\"";
}

std::string raysJson(const RayCounts &r) {
  return fmt::format(R"({{"camera": {}, "shadow": {}, "reflection": {}, "refraction": {}, "total": {}}})",
                     r.camera, r.shadow, r.reflection, r.refraction,
                     r.camera + r.shadow + r.reflection + r.refraction);
}

} // namespace

std::string toJson(const RunStats &s) {
  RayCounts total;
  double build = 0, render = 0, sceneT = 0, write = 0, images = 0;
  uint64_t nonFinite = 0;
  for (const FrameStats &f : s.frames) {
    total += f.rays;
    build += f.accel.buildSeconds;
    render += f.renderSeconds;
    sceneT += f.sceneSeconds;
    write += f.writeSeconds;
    images += f.imageSeconds;
    nonFinite += f.rays.nonFinite;
  }
  std::string out = "{\n";
  out += fmt::format("  \"lray_version\": {},\n", quoted(LRAY_VERSION));
  out += fmt::format("  \"scene\": {},\n  \"backend\": {},\n", quoted(s.scene), quoted(s.backend));
  out += fmt::format("  \"threads\": {},\n  \"width\": {},\n  \"height\": {},\n  \"samples\": {},\n",
                     s.threads, s.width, s.height, s.samples);
  out += fmt::format("  \"times\": {{\"load_script\": {:.6f}, \"scene\": {:.6f}, \"images\": {:.6f}, "
                     "\"build\": {:.6f}, \"render\": {:.6f}, \"write\": {:.6f}, \"total\": {:.6f}}},\n",
                     s.loadSeconds, sceneT, images, build, render, write, s.totalSeconds);
  out += fmt::format("  \"rays\": {},\n", raysJson(total));
  out += fmt::format("  \"non_finite_samples\": {},\n", nonFinite);
  out += fmt::format("  \"peak_memory_bytes\": {},\n", s.peakMemoryBytes);
  out += "  \"frames\": [";
  for (size_t i = 0; i < s.frames.size(); ++i) {
    const FrameStats &f = s.frames[i];
    out += i ? ",\n    " : "\n    ";
    out += fmt::format(
        R"({{"frame": {}, "clock": {}, "file": {}, "entities": {}, "lights": {}, "primitives": {}, "instances": {}, )"
        R"("accel_memory_bytes": {}, "times": {{"scene": {:.6f}, "images": {:.6f}, "build": {:.6f}, "render": {:.6f}, "write": {:.6f}}}, )"
        R"("rays": {}, "non_finite_samples": {}}})",
        f.frame, f.clock, quoted(f.file), f.entities, f.lights, f.accel.primitives, f.accel.instances,
        f.accel.memoryBytes, f.sceneSeconds, f.imageSeconds, f.accel.buildSeconds, f.renderSeconds,
        f.writeSeconds, raysJson(f.rays), f.rays.nonFinite);
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
