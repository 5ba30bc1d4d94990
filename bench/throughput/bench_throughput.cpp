// bench/throughput: LRay's render time against the time Embree alone needs
// for the same rays (issue 34's "traversal share"). One frame of a scene is
// rendered with the Whitted integrator on one thread (the `lray` settings
// given), timed; then rendered again through RecordingAccelerator, and
// every ray it traced is traced again through EmbreeAccelerator::rawSeconds
// (single rays and 8-wide packets where LRay uses them), timed per kind.
//   build/bench_throughput SCENE.lua [-w W] [-H H] [-s N] [--frame F] [--repeats R]
// Prints one JSON line: render seconds (median of R), rays per kind, raw
// Embree seconds per kind (medians of R) and the share raw / render.
#include "accel/embree/embree_accelerator.h"
#include "bindings/scene_script.h"
#include "render/tile_renderer_impl.h"
#include "shading/image_cache.h"
#include "recording_accelerator.h"

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

} // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_throughput SCENE.lua [-w W] [-H H] [-s N] [--frame F] "
                         "[--repeats R]\n");
    return 2;
  }
  std::string scenePath = argv[1];
  int width = 640, height = 360, samples = 3, frame = 0, repeats = 3;
  for (int i = 2; i + 1 < argc; i += 2) {
    const int v = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "-w")) width = v;
    else if (!std::strcmp(argv[i], "-H")) height = v;
    else if (!std::strcmp(argv[i], "-s")) samples = v;
    else if (!std::strcmp(argv[i], "--frame")) frame = v;
    else if (!std::strcmp(argv[i], "--repeats")) repeats = std::max(1, v);
    else {
      std::fprintf(stderr, "bench_throughput: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  try {
    SceneScript script(scenePath);
    SceneInfo info = script.info();
    Scene scene = script.buildFrame(info.clockForFrame(frame));
    ImageCache images(false);
    images.load(scene);
    EmbreeAccelerator embree(scene);
    FrameSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samples = samples;
    settings.frameIndex = frame;

    std::vector<double> renders;
    for (int r = 0; r < repeats; ++r) {
      Film film(width, height);
      RayCounts counts;
      const auto t0 = std::chrono::steady_clock::now();
      renderTiles<Integrator<EmbreeAccelerator>>(embree, scene, images, settings, film, counts,
                                                 nullptr);
      renders.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    RecordingAccelerator<EmbreeAccelerator> recorder(embree);
    {
      Film film(width, height);
      RayCounts counts;
      renderTiles<Integrator<RecordingAccelerator<EmbreeAccelerator>>>(
          recorder, scene, images, settings, film, counts, nullptr);
    }
    const RecordedRays rays = recorder.recorded();
    using Q = EmbreeAccelerator::RawQuery;
    auto raw = [&](const std::vector<Ray> &v, Q q) {
      std::vector<double> t;
      for (int r = 0; r < repeats; ++r) t.push_back(embree.rawSeconds(v.data(), v.size(), q));
      return median(t);
    };
    const double camera = raw(rays.camera, Q::ClosestPackets),
                 secondary = raw(rays.secondary, Q::Closest),
                 shadow = raw(rays.shadow, Q::Occlusion),
                 shadowPackets = raw(rays.shadowPackets, Q::OcclusionPackets);
    const double render = median(renders), total = camera + secondary + shadow + shadowPackets;
    std::printf("{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"samples\": %d, "
                "\"render_s\": %.4f, \"rays\": {\"camera\": %zu, \"secondary\": %zu, "
                "\"shadow\": %zu, \"shadow_packets\": %zu}, \"raw_embree_s\": {\"camera\": %.4f, "
                "\"secondary\": %.4f, \"shadow\": %.4f, \"shadow_packets\": %.4f, \"total\": "
                "%.4f}, \"traversal_share\": %.3f}\n",
                scenePath.c_str(), width, height, samples, render, rays.camera.size(),
                rays.secondary.size(), rays.shadow.size(), rays.shadowPackets.size(), camera,
                secondary, shadow, shadowPackets, total, total / render);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench_throughput: %s\n", e.what());
    return 1;
  }
  return 0;
}
