// Pipeline: application (live preview). See watch_loop.h.
#include "app/watch/watch_loop.h"
#include "util/printable_text.h"

#include "run/limit_options.h"
#include "run/run_plan.h"
#include "run/sampling_options.h"
#include "run/render_stats.h"
#include "app/watch/file_watcher.h"
#include "app/watch/preview_server.h"
#include "app/watch/preview_state.h"
#include "bindings/scene_script.h"
#include "render/image_writer.h"
#include "render/renderer.h"
#include "run/frame_pipeline.h"
#include "run/limit_options.h"
#include "run/render_stats.h"
#include "run/run_plan.h"
#include "run/sampling_options.h"
#include "shading/image_cache.h"
#include "render/backends.h"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

namespace lray {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> gStop{false}; // lock-free: safe in a signal handler
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void onStopSignal(int) {
  gStop = true;
  // A second Ctrl-C ends the process at once.
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}


/// One render of the scene as it is on disk now.
class Render {
public:
  Render(const Options &opt, PreviewState &state, int frame, std::string backend,
         const std::atomic<bool> &cancel)
      : opt_(opt), state_(state), frame_(frame), backend_(std::move(backend)), cancel_(cancel) {}

  /// Renders until done or cancelled; publishes each image. The files the
  /// script read (for the watcher), empty when it failed to load.
  std::vector<std::string> run() {
    start_ = std::chrono::steady_clock::now();
    status_.scene = opt_.scenePath;
    status_.backend = backend_;
    for (const BackendEntry &b : backends()) status_.backends.push_back(b.name);
    std::optional<SceneScript> loaded;
    try {
      SceneScript &script = loaded.emplace(opt_.scenePath, scriptOptionsOf(opt_));
      Options fixed = opt_;
      fixed.firstFrame.reset();
      fixed.lastFrame.reset();
      const SceneInfo info = effectiveSceneInfo(script.info(), fixed);
      frame_ = std::clamp(frame_, 0, info.frames - 1);
      status_.frame = frame_;
      status_.frames = info.frames;
      status_.clock = info.clockForFrame(frame_);
      status_.width = info.imageWidth;
      status_.height = info.imageHeight;
      const std::string stem = fs::path(opt_.scenePath).stem().string();
      // Beside the scene, a name of its own: Save never replaces a user's file.
      const std::string fileName =
          opt_.outDir.empty()
              ? frameFileName(stem + "-preview", frame_, info.frames, ImageFormat::Png)
              : frameFileName(stem, frame_, info.frames, ImageFormat::Png);
      const fs::path folder =
          opt_.outDir.empty() ? fs::path(opt_.scenePath).parent_path() : fs::path(opt_.outDir);
      savePath_ = (folder / fileName).string();
      if (!opt_.outDir.empty()) {
        fs::create_directories(opt_.outDir);
        outPath_ = (fs::path(opt_.outDir) / frameFileName(stem, frame_, info.frames, opt_.format))
                       .string();
      }

      FrameStats stats;
      stats.frame = frame_;
      stats.clock = status_.clock;
      auto t0 = std::chrono::steady_clock::now();
      Scene scene = buildFrameScene(script, info, frame_, stats.sceneCalls);
      stats.sceneSeconds = secondsSince(t0);
      ImageCache images(opt_.linear); // afresh: an image file may have changed
      images.load(scene);
      std::unique_ptr<Accelerator> accel = makeAccelerator(backend_, scene);
      stats.accel = accel->stats();
      stats.entities = scene.entities.size();
      stats.lights = scene.lights.size();

      // A first look: one sample through each pixel's centre.
      FrameSettings quick;
      quick.width = info.imageWidth;
      quick.height = info.imageHeight;
      quick.samples = 1;
      quick.frameIndex = frame_;
      quick.seed = opt_.seed;
      RayCounts quickRays;
      Film first = renderFrame(scene, *accel, images, quick, quickRays);
      publish(first, 0, "rendering", stats);
      if (cancel_) return script.filesRead();

      // Then the adaptive passes, each shown as it finishes.
      FrameSettings settings = watchSampling(info, opt_);
      sampling_ = settings;
      settings.width = info.imageWidth;
      settings.height = info.imageHeight;
      settings.frameIndex = frame_;
      settings.cancel = &cancel_;
      settings.onPass = [&](const Film &film) {
        if (!cancel_) publish(film, film.report.passes, "rendering", stats);
      };
      t0 = std::chrono::steady_clock::now();
      Film film = renderFrame(scene, *accel, images, settings, stats.rays);
      stats.renderSeconds = secondsSince(t0);
      stats.sampling = film.report;
      if (!film.report.cancelled) publish(film, film.report.passes, "done", stats);
      return script.filesRead();
    } catch (const ScriptLoadError &e) {
      // The files read before the error: an included file that fails to
      // load is watched, so fixing it renders again.
      fail(e.what());
      return e.filesRead;
    } catch (const std::exception &e) {
      fail(e.what());
    } catch (...) {
      fail("the render failed");
    }
    return loaded ? loaded->filesRead() : std::vector<std::string>{};
  }

private:
  void fail(const std::string &message) {
    status_.state = "error";
    status_.message = message;
    status_.seconds = secondsSince(start_);
    state_.publish(status_);
    if (!opt_.quiet) std::fprintf(stderr, "lray: error: %s\n", printableText(message).c_str());
  }

  void publish(const Film &film, int pass, const char *what, const FrameStats &stats) {
    status_.state = what;
    status_.message.clear();
    status_.pass = pass;
    status_.samplesPerPixel =
        film.pixels() ? double(film.report.samples) / double(film.pixels()) : 0;
    if (pass == 0) status_.samplesPerPixel = 1;
    status_.errorMean = film.report.meanError;
    status_.errorMax = film.report.maxError;
    status_.seconds = secondsSince(start_);
    RunStats run;
    run.scene = opt_.scenePath;
    run.backend = backend_;
    run.width = status_.width;
    run.height = status_.height;
    run.sampling = sampling_;
    run.frames.push_back(stats);
    run.frames.back().sampling = film.report;
    status_.statsJson = toJson(run);
    state_.publish(encodePng(film, opt_.linear), status_, savePath_);
    if (!outPath_.empty()) writeImage(film, outPath_, opt_.format, opt_.linear);
  }

  const Options &opt_;
  PreviewState &state_;
  int frame_;
  std::string backend_;
  const std::atomic<bool> &cancel_;
  PreviewStatus status_;
  std::string outPath_, savePath_;
  FrameSettings sampling_;
  std::chrono::steady_clock::time_point start_;
};

} // namespace

FrameSettings watchSampling(const SceneInfo &info, const Options &options) {
  Options o = options;
  if (!o.noiseThreshold && !(info.noiseThreshold > 0)) o.noiseThreshold = 0.01;
  if (!o.minSamples) o.minSamples = std::min(4, o.maxSamples.value_or(4));
  if (!o.maxSamples) o.maxSamples = std::max(256, *o.minSamples);
  o.samples.reset();
  o.timeLimit = 0;
  return samplingSettings(info, o);
}

int runWatch(const Options &opt) {
  if (!fs::is_regular_file(opt.scenePath))
    throw SceneError("scene file '" + opt.scenePath + "' does not exist or is not a file");
  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(threads));
  FileWatcher watcher; // first: its failure must not leave a server starting up
  PreviewState state;
  std::optional<PreviewServer> server;
  if (!opt.serve.empty()) {
    server.emplace(state, opt.serveHost, opt.servePort);
    std::printf("lray: preview at %s (Ctrl-C to stop)\n", server->url().c_str());
  } else if (!opt.quiet) {
    std::printf("lray: watching %s (Ctrl-C to stop)\n", opt.scenePath.c_str());
  }
  std::fflush(stdout);
  gStop = false;
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);

  std::vector<std::string> files; // the last good load's, beside the scene
  int frame = opt.firstFrame.value_or(0);
  std::string backend = backendName(opt.backend);
  auto watchAll = [&] {
    std::vector<std::string> all = files;
    all.push_back(opt.scenePath);
    watcher.watch(all);
  };
  watchAll();
  constexpr auto kQuiet = std::chrono::milliseconds(120); // debounce of a save
  while (!gStop) {
    if (auto r = state.takeRequest()) {
      if (r->frame) frame = *r->frame;
      if (r->backend)
        for (const BackendEntry &b : backends())
          if (b.name == *r->backend) backend = b.name;
    }
    std::atomic<bool> cancel{false}, done{false};
    std::vector<std::string> read;
    const auto renderStart = fs::file_time_type::clock::now();
    std::thread worker([&] {
      read = Render(opt, state, frame, backend, cancel).run();
      done = true;
    });
    // While it renders: an edit, a request from the page or Ctrl-C cancels
    // it (at the end of the pass under way) and starts the next one.
    bool again = false;
    while (!done) {
      if (watcher.waitForChange(std::chrono::milliseconds(50), kQuiet) || state.requestPending() ||
          gStop) {
        cancel = true;
        again = true;
        break;
      }
    }
    worker.join();
    // A file first read by this render was not watched while it ran: if it
    // changed since the render began, render again.
    for (const std::string &f : read) {
      if (std::find(files.begin(), files.end(), f) != files.end()) continue;
      std::error_code ec;
      if (fs::last_write_time(f, ec) >= renderStart && !ec) again = true;
    }
    // Watched from now on: every file any load has read (a file dropped from
    // the scene stays watched; harmless).
    for (const std::string &f : read)
      if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
    watchAll();
    if (again) continue;
    while (!gStop && !state.requestPending() &&
           !watcher.waitForChange(std::chrono::milliseconds(200), kQuiet)) {
    }
  }
  if (server) server->stop();
  if (!opt.quiet) std::printf("lray: preview stopped\n");
  return 0;
}

} // namespace lray
