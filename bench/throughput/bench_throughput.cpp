// bench/throughput: LRay's render time against the time its backend alone
// needs for the same rays (issue 34's "traversal share"). One frame of a
// scene is rendered with the Whitted integrator on one thread (the `lray`
// settings given), timed; then rendered again through RecordingAccelerator,
// and every ray it traced is traced again through the backend's rawSeconds
// (Embree's calls, or the kd-tree's walks: single rays, and packets where
// LRay uses them), timed per kind.
//   build/bench_throughput SCENE.lua [-w W] [-H H] [-s N] [--frame F] [--repeats R]
//       [--backend embree|kdtree] [--shutter S] [--noise-threshold T [--min-samples N]
//       [--max-samples N]] [--light-sampling all|spread] [--every-shadow-ray]
// (--shutter: the frame with its shutter open, as `lray --shutter`: each
// recorded ray keeps its time, and the replay asks the backend at it.
// --noise-threshold: adaptive sampling as `lray` does it, its defaults
// included. --every-shadow-ray: the rays are recorded from a render with
// `--no-shadow-skips`, so the shadow rays LRay settles itself are traced
// by the backend too; the render timed keeps its skips.)
// Prints one JSON line: render seconds (median of R), rays per kind, raw
// backend seconds per kind (medians of R) and the share raw / render.
#include "accel/embree/embree_accelerator.h"
#include "accel/kdtree/kdtree_accelerator.h"
#include "bindings/scene_script.h"
#include "render/tile_renderer_impl.h"
#include "shading/image_cache.h"
#include "recording_accelerator.h"
#include "run/frame_pipeline.h"
#include "run/sampling_options.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

using namespace lray;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// The bench's own options; the sampling ones go to `lray`'s Options, so
/// that a frame is sampled as `lray` would sample it (run/sampling_options.h).
struct BenchOptions {
  int frame = 0, repeats = 3;
  bool everyShadowRay = false;
};

/// Renders with `accel` R times, records one more render's rays, replays
/// them through accel.rawSeconds and prints the JSON line.
template <class Accel>
void measure(const Accel &accel, const char *backend, const Scene &scene, const ImageCache &images,
             const std::string &scenePath, const FrameSettings &sampling, const BenchOptions &o) {
  FrameSettings settings = sampling;
  std::vector<double> renders;
  for (int r = 0; r < o.repeats; ++r) {
    Film film(settings.width, settings.height);
    RayCounts counts;
    const auto t0 = std::chrono::steady_clock::now();
    renderTiles<Integrator<Accel>>(accel, scene, images, settings, film, counts, nullptr);
    renders.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  RecordingAccelerator<Accel> recorder(accel);
  settings.shadowSkips = !o.everyShadowRay;
  {
    Film film(settings.width, settings.height);
    RayCounts counts;
    renderTiles<Integrator<RecordingAccelerator<Accel>>>(recorder, scene, images, settings, film,
                                                         counts, nullptr);
  }
  const RecordedRays rays = recorder.recorded();
  auto raw = [&](const std::vector<Ray> &v, RawQuery q) {
    std::vector<double> t;
    for (int r = 0; r < o.repeats; ++r) t.push_back(accel.rawSeconds(v.data(), v.size(), q));
    return median(t);
  };
  const double camera = raw(rays.camera, RawQuery::ClosestPackets),
               secondary = raw(rays.secondary, RawQuery::Closest),
               shadow = raw(rays.shadow, RawQuery::Occlusion),
               shadowPackets = raw(rays.shadowPackets, RawQuery::OcclusionPackets);
  const double render = median(renders), total = camera + secondary + shadow + shadowPackets;
  std::printf("{\"scene\": \"%s\", \"backend\": \"%s\", \"width\": %d, \"height\": %d, "
              "\"samples\": %d, \"noise_threshold\": %g, \"every_shadow_ray\": %s, "
              "\"render_s\": %.4f, \"rays\": {\"camera\": %zu, "
              "\"secondary\": %zu, \"shadow\": %zu, \"shadow_packets\": %zu}, "
              "\"raw_s\": {\"camera\": %.4f, \"secondary\": %.4f, \"shadow\": %.4f, "
              "\"shadow_packets\": %.4f, \"total\": %.4f}, \"traversal_share\": %.3f}\n",
              scenePath.c_str(), backend, settings.width, settings.height, settings.samples,
              settings.adaptiveSettings.noiseThreshold,
              o.everyShadowRay ? "true" : "false", render,
              rays.camera.size(), rays.secondary.size(), rays.shadow.size(),
              rays.shadowPackets.size(), camera, secondary, shadow, shadowPackets, total,
              total / render);
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_throughput SCENE.lua [-w W] [-H H] [-s N] [--frame F] "
                         "[--repeats R] [--backend embree|kdtree] [--shutter S] "
                         "[--noise-threshold T] [--min-samples N] [--max-samples N] "
                         "[--light-sampling all|spread] [--every-shadow-ray]\n");
    return 2;
  }
  Options cli; // lray's: the size and the sampling
  cli.scenePath = argv[1];
  cli.width = 640;
  cli.height = 360;
  BenchOptions o;
  std::string backend = "embree";
  for (int i = 2; i < argc; i += 2) {
    if (!std::strcmp(argv[i], "--every-shadow-ray")) {
      o.everyShadowRay = true;
      --i;
      continue;
    }
    if (i + 1 == argc) {
      std::fprintf(stderr, "bench_throughput: %s needs a value\n", argv[i]);
      return 2;
    }
    const int v = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "-w")) cli.width = v;
    else if (!std::strcmp(argv[i], "-H")) cli.height = v;
    else if (!std::strcmp(argv[i], "-s")) cli.samples = v;
    else if (!std::strcmp(argv[i], "--frame")) o.frame = v;
    else if (!std::strcmp(argv[i], "--repeats")) o.repeats = std::max(1, v);
    else if (!std::strcmp(argv[i], "--shutter")) cli.shutter = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--noise-threshold"))
      cli.noiseThreshold = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--min-samples")) cli.minSamples = v;
    else if (!std::strcmp(argv[i], "--max-samples")) cli.maxSamples = v;
    else if (!std::strcmp(argv[i], "--light-sampling") && !std::strcmp(argv[i + 1], "all"))
      cli.lightSampling = LightSampling::All;
    else if (!std::strcmp(argv[i], "--light-sampling") && !std::strcmp(argv[i + 1], "spread"))
      cli.lightSampling = LightSampling::Spread;
    else if (!std::strcmp(argv[i], "--backend") &&
             (!std::strcmp(argv[i + 1], "embree") || !std::strcmp(argv[i + 1], "kdtree")))
      backend = argv[i + 1];
    else {
      std::fprintf(stderr, "bench_throughput: bad option %s %s\n", argv[i], argv[i + 1]);
      return 2;
    }
  }
  // -s 3 unless adaptive (as `lray`, -s is fixed sampling's).
  if (!cli.samples && cli.noiseThreshold.value_or(0) <= 0) cli.samples = 3;
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  try {
    SceneScript script(cli.scenePath);
    const SceneInfo info = effectiveSceneInfo(script.info(), cli);
    FrameSettings sampling = samplingSettings(info, cli);
    sampling.integrator = IntegratorKind::Whitted; // the one this bench renders with
    sampling.width = info.imageWidth;
    sampling.height = info.imageHeight;
    sampling.samples = info.samples;
    sampling.frameIndex = o.frame;
    int calls = 0;
    Scene scene = buildFrameScene(script, info, o.frame, calls);
    ImageCache images(false);
    images.load(scene);
    if (backend == "kdtree")
      measure(KdTreeAccelerator(scene), "kdtree", scene, images, cli.scenePath, sampling, o);
    else measure(EmbreeAccelerator(scene), "embree", scene, images, cli.scenePath, sampling, o);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench_throughput: %s\n", e.what());
    return 1;
  }
  return 0;
}
