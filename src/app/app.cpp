// Pipeline: application. The frame loop of the lray CLI.
#include "app/app.h"
#include "util/printable_text.h"

#include "app/frame_writer.h"
#include "app/progress_bar.h"
#include "app/watch/watch_loop.h"
#include "bindings/scene_script.h"
#include "render/output_file.h"
#include "render/tile_file.h"
#include "run/frame_pipeline.h"
#include "run/limit_options.h"
#include "run/render_stats.h"
#include "run/run_plan.h"
#include "shading/image_cache.h"
#include "render/backends.h"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <new>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace lray {

namespace fs = std::filesystem;

namespace {

/// What run() is doing, for the last-resort error handler: an error that
/// is not a SceneError is a bug or a resource failure, and the user should
/// learn at least what LRay was doing when it happened.
std::string gActivity = "starting";

void setActivity(std::string what) { gActivity = std::move(what); }

// Creates the output folder and proves it is writable before any work is done.
void prepareOutDir(const std::string &dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw SceneError("cannot create output folder '" + dir + "': " +
                     (ec ? ec.message() : std::string("a file of that name exists")));
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw SceneError("output folder '" + dir + "' is not writable");
}

std::string fileBytes(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// --info: the run plan, with what a render farm needs to split the work.
int printInfo(const Options &opt) {
  SceneScript script(opt.scenePath, scriptOptionsOf(opt));
  const RunPlan plan = makeRunPlan(opt, script.info());
  std::printf("%s\n", infoJson(plan, fileBytes(opt.scenePath), opt.infoTiles).c_str());
  return 0;
}

int run(const Options &opt) {
  auto start = std::chrono::steady_clock::now();
  RunStats stats;
  if (!fs::is_regular_file(opt.scenePath))
    throw SceneError("scene file '" + opt.scenePath + "' does not exist or is not a file");
  if (opt.info) {
    setActivity("reading the scene's frames (--info)");
    return printInfo(opt);
  }
  // Fail on an unusable output before spending time on the script.
  prepareOutDir(opt.outDir);
  if (!opt.statsPath.empty()) {
    fs::path statsDir = fs::path(opt.statsPath).parent_path();
    if (!statsDir.empty() && !fs::is_directory(statsDir))
      throw SceneError("--stats: folder '" + statsDir.string() + "' does not exist");
    if (fs::is_directory(opt.statsPath))
      throw SceneError("cannot write statistics '" + opt.statsPath +
                       "': a folder of that name is in the way");
  }

  int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(threads));
  // TBB's one-time set-up (its scheduler's library search, the CPU
  // count) now, before the script: left to the first parallel loop it
  // fell inside the first frame's render time unless a backend (Embree's
  // device) had already paid it.
  tbb::task_arena().initialize();

  auto t0 = std::chrono::steady_clock::now();
  setActivity("loading the scene");
  SceneScript script(opt.scenePath, scriptOptionsOf(opt));
  stats.loadSeconds = secondsSince(t0);
  const RunPlan plan = makeRunPlan(opt, script.info());
  const SceneInfo &info = plan.info;
  stats.scene = opt.scenePath;
  stats.backend = backendName(plan.backend);
  stats.threads = threads;
  stats.width = info.imageWidth;
  stats.height = info.imageHeight;
  stats.samples = info.samples;
  stats.sampling = plan.frameSettings;
  stats.settings = plan.settingsJson();
  const bool tiled = plan.tiled();
  const PixelWindow &window = plan.frameSettings.crop;
  const std::string fingerprint = tiled ? plan.fingerprint(fileBytes(opt.scenePath)) : "";

  ImageCache images(opt.linear);
  ProgressBar bar(!opt.quiet);
  bool warned = false;
  FrameWriter writer(threads, [](const std::string &path) { setActivity("writing " + path); });
  for (int frame : plan.frames()) {
    setActivity(fmt::format("preparing frame {}", frame));
    FrameStats frameStats;
    const std::string finalName = plan.finalName(frame);
    const std::string path = (fs::path(opt.outDir) / plan.outputName(frame)).string();
    frameStats.file = path;
    if (opt.skipExisting) {
      // A tile is done when it exists, or when its frame does (merged).
      const std::string finalPath = (fs::path(opt.outDir) / finalName).string();
      std::string done;
      if (tiled ? completeTile(path, {finalName, opt.format, opt.linear, info.imageWidth,
                                      info.imageHeight, window, fingerprint})
                : completeImage(path, opt.format, info.imageWidth, info.imageHeight))
        done = path;
      else if (tiled && completeImage(finalPath, opt.format, info.imageWidth, info.imageHeight))
        done = finalPath;
      if (!done.empty()) {
        if (!opt.quiet) std::printf("%s exists: skipped\n", printableText(done).c_str());
        continue;
      }
    }
    setActivity(fmt::format("rendering frame {}", frame));
    bar.start(fmt::format("frame {}/{}", frame + 1, info.frames));
    Film film = renderScriptFrame(
        script, info, frame, stats.backend, images, frameStats,
        [&bar](size_t done, size_t total) { bar.update(done, total); }, plan.frameSettings);
    bar.finish(frameStats.renderSeconds);
    if (!warned)
      for (const std::string &warning : frameStats.warnings)
        std::fprintf(stderr, "lray: warning: %s\n", printableText(warning).c_str());
    warned = true;

    // Written while the next frame renders; its line and statistics follow
    // once the file is complete.
    auto done = std::make_shared<const Film>(std::move(film));
    const size_t filmBytes = done->memoryBytes();
    std::function<void()> write;
    if (tiled)
      write = [done, path, tile = TileHeader{finalName, opt.format, opt.linear, info.imageWidth,
                                             info.imageHeight, window, fingerprint}] {
        writeTile(*done, tile, path);
      };
    else
      write = [done, path, format = opt.format, linear = opt.linear] {
        writeImage(*done, path, format, linear);
      };
    writer.submit(path, filmBytes, std::move(write),
                  [&stats, &bar, &opt, frameStats, path](double seconds) mutable {
                    frameStats.writeSeconds = seconds;
                    if (!opt.quiet && !bar.enabled())
                      std::printf("%s (%.2f s)\n", printableText(path).c_str(),
                                  frameStats.renderSeconds + frameStats.sceneSeconds);
                    stats.frames.push_back(std::move(frameStats));
                  });
  }
  setActivity("writing the last frames");
  writer.finish();
  stats.totalSeconds = secondsSince(start);
  stats.peakMemoryBytes = peakMemoryBytes();
  setActivity("writing " + opt.statsPath);
  if (!opt.statsPath.empty()) writeOutputFile(opt.statsPath, "statistics", toJson(stats));
  return 0;
}

} // namespace

std::string describeUnexpectedError(const std::exception &e) {
  if (dynamic_cast<const std::bad_alloc *>(&e)) return "out of memory";
  if (dynamic_cast<const std::length_error *>(&e)) return "a size too large to allocate";
  if (dynamic_cast<const std::filesystem::filesystem_error *>(&e)) return e.what();
  // A thread that could not start: under an address-space limit (ulimit
  // -v) there is no room for its stack, or a limit on processes bites.
  // std::thread says so by its error code, TBB's worker pool by its text.
  const std::string threadRefused =
      "the system refused to start a thread (not enough memory, or too many threads): ";
  // Threads, files and other resources the system refused.
  if (const auto *system = dynamic_cast<const std::system_error *>(&e)) {
    if (system->code() == std::errc::resource_unavailable_try_again)
      return threadRefused + system->code().message();
    return "the system refused: " + system->code().message();
  }
  std::string what = e.what();
  if (const std::string tbb = "pthread_create has failed: "; what.rfind(tbb, 0) == 0)
    return threadRefused + what.substr(tbb.size());
  for (size_t at; (at = what.find("std::")) != std::string::npos;) what.erase(at, 5);
  return "internal error (" + what + "); please report it with the scene";
}

int runLray(int argc, const char *const *argv) {
  ParseResult parsed = parseOptions(argc, argv);
  if (!parsed.options) {
    // Help and version are LRay's own text; a usage error quotes the user's.
    const std::string message =
        parsed.exitCode == 0 ? parsed.message : printableText(parsed.message);
    std::fputs(message.c_str(), parsed.exitCode == 0 ? stdout : stderr);
    if (!message.empty() && message.back() != '\n')
      std::fputc('\n', parsed.exitCode == 0 ? stdout : stderr);
    return parsed.exitCode;
  }
  try {
    if (parsed.options->watch) {
      setActivity("watching the scene (--watch)");
      return runWatch(*parsed.options);
    }
    return run(*parsed.options);
  } catch (const SceneError &e) {
    std::fprintf(stderr, "lray: error: %s\n", printableText(e.what()).c_str());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "lray: error: %s\n",
                 printableText(parsed.options->scenePath + ": " + gActivity + ": " +
                               describeUnexpectedError(e))
                     .c_str());
  } catch (...) {
    std::fprintf(stderr, "lray: error: %s\n",
                 printableText(parsed.options->scenePath + ": " + gActivity + ": an unknown error")
                     .c_str());
  }
  return 1;
}

} // namespace lray
