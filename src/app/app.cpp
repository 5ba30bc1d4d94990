// Pipeline: application. The frame loop of the lray CLI.
#include "app/app.h"

#include "app/progress_bar.h"
#include "app/render_stats.h"
#include "bindings/scene_script.h"
#include "scene/scene_checks.h"
#include "app/frame_pipeline.h"
#include "app/watch/watch_loop.h"
#include "render/tile_file.h"
#include "shading/image_cache.h"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
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

void writeTextAtomically(const std::string &path, const std::string &text) {
  std::string tmp = path + ".tmp" + std::to_string(getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out.flush()) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw SceneError("cannot write '" + path + "'");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    // A directory under the final name, say: the temporary file must not stay.
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw SceneError("cannot write '" + path + "': " + ec.message());
  }
}

/// --info: what a render farm needs to split the work.
int printInfo(const Options &opt) {
  SceneScript script(opt.scenePath, scriptOptionsOf(opt));
  const SceneInfo info = effectiveSceneInfo(script.info(), opt);
  const FrameSettings s = samplingSettings(info, opt);
  std::printf("{\"frames\":%d,\"width\":%d,\"height\":%d,\"samples\":%d,\"adaptive\":%s,"
              "\"tile_rows\":%d,\"start_clock\":%.17g,\"end_clock\":%.17g}\n",
              info.frames, info.imageWidth, info.imageHeight, info.samples,
              s.adaptive ? "true" : "false", (info.imageHeight + kTileSize - 1) / kTileSize,
              info.startClock, info.endClock);
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
  }

  int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(threads));

  auto t0 = std::chrono::steady_clock::now();
  setActivity("loading the scene");
  SceneScript script(opt.scenePath, scriptOptionsOf(opt));
  stats.loadSeconds = secondsSince(t0);
  const SceneInfo info = effectiveSceneInfo(script.info(), opt);

  const FrameSettings sampling = samplingSettings(info, opt);

  int first = opt.firstFrame.value_or(0);
  int last = opt.lastFrame.value_or(info.frames - 1);
  std::string stem = fs::path(opt.scenePath).stem().string();
  stats.scene = opt.scenePath;
  stats.backend = backendName(opt.backend);
  stats.threads = threads;
  stats.width = info.imageWidth;
  stats.height = info.imageHeight;
  stats.samples = info.samples;
  stats.sampling = sampling;

  // --tile and --crop: one window of each frame, written as a tile.
  FrameSettings frameSampling = sampling;
  if (opt.tile) {
    frameSampling.crop = tileBand(opt.tile->first, opt.tile->second, info.imageWidth, info.imageHeight);
  } else if (opt.crop) {
    const PixelWindow &c = *opt.crop;
    if (c.x1 > info.imageWidth || c.y1 > info.imageHeight)
      throw SceneError(fmt::format("--crop {}:{}:{}:{}: the window reaches outside the {} x {} frame",
                                   c.x0, c.y0, c.x1, c.y1, info.imageWidth, info.imageHeight));
    frameSampling.crop = c;
  }
  const bool tiled = !frameSampling.crop.empty();
  const PixelWindow &window = frameSampling.crop;
  std::string fingerprint;
  if (tiled) {
    std::ifstream in(opt.scenePath, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const AdaptiveSettings &a = sampling.adaptiveSettings;
    fingerprint = renderFingerprint(
        bytes, fmt::format("{}x{} samples {} adaptive {} {} {} {} seed {} light {} linear {} aovs {} backend {}",
                           info.imageWidth, info.imageHeight, info.samples, sampling.adaptive,
                           a.noiseThreshold, a.minSamples, a.maxSamples, sampling.seed,
                           static_cast<int>(sampling.lightSampling), opt.linear, opt.aovs,
                           stats.backend));
  }

  ImageCache images(opt.linear);
  ProgressBar bar(!opt.quiet);
  bool warned = false;
  for (int frame = first; frame <= last; frame += opt.frameStep) {
    setActivity(fmt::format("preparing frame {}", frame));
    FrameStats frameStats;
    const std::string finalName = frameFileName(stem, frame, info.frames, opt.format);
    const std::string fileName = !tiled      ? finalName
                                 : opt.tile ? tileFileName(finalName, opt.tile->first, opt.tile->second)
                                            : cropFileName(finalName, window);
    const std::string path = (fs::path(opt.outDir) / fileName).string();
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
        if (!opt.quiet) std::printf("%s exists: skipped\n", done.c_str());
        continue;
      }
    }
    setActivity(fmt::format("rendering frame {}", frame));
    bar.start(fmt::format("frame {}/{}", frame + 1, info.frames));
    Film film = renderScriptFrame(
        script, info, frame, stats.backend, images, frameStats,
        [&bar](size_t done, size_t total) { bar.update(done, total); }, frameSampling);
    bar.finish(frameStats.renderSeconds);
    if (!warned)
      for (const std::string &warning : frameStats.warnings)
        std::fprintf(stderr, "lray: warning: %s\n", warning.c_str());
    warned = true;

    t0 = std::chrono::steady_clock::now();
    setActivity("writing " + path);
    if (tiled)
      writeTile(film, {finalName, opt.format, opt.linear, info.imageWidth, info.imageHeight, window, fingerprint},
                path);
    else
      writeImage(film, path, opt.format, opt.linear);
    frameStats.writeSeconds = secondsSince(t0);
    if (!opt.quiet && !bar.enabled())
      std::printf("%s (%.2f s)\n", path.c_str(), frameStats.renderSeconds + frameStats.sceneSeconds);
    stats.frames.push_back(std::move(frameStats));
  }
  stats.totalSeconds = secondsSince(start);
  stats.peakMemoryBytes = peakMemoryBytes();
  setActivity("writing " + opt.statsPath);
  if (!opt.statsPath.empty()) writeTextAtomically(opt.statsPath, toJson(stats));
  return 0;
}

} // namespace

std::string describeUnexpectedError(const std::exception &e) {
  if (dynamic_cast<const std::bad_alloc *>(&e)) return "out of memory";
  if (dynamic_cast<const std::length_error *>(&e)) return "a size too large to allocate";
  if (dynamic_cast<const std::filesystem::filesystem_error *>(&e)) return e.what();
  // Threads, files and other resources the system refused.
  if (const auto *system = dynamic_cast<const std::system_error *>(&e))
    return "the system refused: " + system->code().message();
  std::string what = e.what();
  for (size_t at; (at = what.find("std::")) != std::string::npos;) what.erase(at, 5);
  return "internal error (" + what + "); please report it with the scene";
}

ScriptOptions scriptOptionsOf(const Options &opt) {
  ScriptOptions s;
  s.unsafe = opt.unsafe;
  s.timeoutSeconds = opt.scriptTimeout;
  s.memoryLimitBytes = opt.scriptMemory;
  s.allowRead = opt.allowRead;
  s.maxFileBytes = opt.maxFileBytes;
  s.maxPixels = static_cast<uint64_t>(opt.maxPixels);
  s.maxLightSamples = static_cast<uint64_t>(std::min(opt.maxLightSamples, 4e18));
  return s;
}

std::string frameFileName(const std::string &stem, int frame, int frameCount, ImageFormat format) {
  std::string ext = formatExtension(format);
  if (frameCount <= 1) return stem + "." + ext;
  return fmt::format("{}{:04d}.{}", stem, frame, ext);
}

SceneInfo effectiveSceneInfo(const SceneInfo &fromScript, const Options &options) {
  SceneInfo info = fromScript;
  if (options.width) info.imageWidth = *options.width;
  if (options.height) info.imageHeight = *options.height;
  if (options.samples) info.samples = *options.samples;
  validateSceneInfo(info, static_cast<uint64_t>(options.maxPixels), options.scenePath);
  if (options.lastFrame && *options.lastFrame >= info.frames)
    throw SceneError(fmt::format("--frames {}:{}: the scene has {} frame{} (0 to {})",
                                 *options.firstFrame, *options.lastFrame, info.frames,
                                 info.frames == 1 ? "" : "s", info.frames - 1));
  return info;
}

FrameSettings samplingSettings(const SceneInfo &info, const Options &options) {
  FrameSettings s;
  const double threshold = options.noiseThreshold.value_or(info.noiseThreshold);
  s.adaptive = threshold > 0 || options.timeLimit > 0;
  if (!s.adaptive && (options.minSamples || options.maxSamples))
    throw SceneError("--min-samples and --max-samples apply to adaptive sampling: give "
                     "--noise-threshold or --time-limit too (or set scene_info.noise_threshold)");
  AdaptiveSettings &a = s.adaptiveSettings;
  a.noiseThreshold = threshold;
  a.timeLimit = options.timeLimit;
  a.maxSamples = options.maxSamples.value_or(std::max(a.maxSamples, options.minSamples.value_or(0)));
  a.minSamples = options.minSamples.value_or(std::min(a.minSamples, a.maxSamples));
  if (a.minSamples > a.maxSamples)
    throw SceneError(fmt::format("--min-samples ({}) is above --max-samples ({})", a.minSamples,
                                 a.maxSamples));
  // The first pass's samples are split into two halves for the estimate;
  // 1 is the centre-first pass (tile_renderer_impl.h).
  if (a.minSamples > 1 && a.minSamples % 2 && a.minSamples < a.maxSamples) ++a.minSamples;
  s.aovs = options.aovs;
  s.seed = options.seed;
  s.shadowSkips = !options.noShadowSkips;
  s.lightSampling =
      options.lightSampling.value_or(s.adaptive ? LightSampling::Spread : LightSampling::All);
  if (s.adaptive) {
    const long double work = static_cast<long double>(info.imageWidth) * info.imageHeight *
                             a.maxSamples;
    if (work > static_cast<long double>(options.maxPixels))
      throw SceneError(fmt::format(
          "{}: image_width * image_height * max samples = {} exceeds the limit of {} (lower "
          "--max-samples or raise --max-pixels)",
          options.scenePath, static_cast<unsigned long long>(work),
          static_cast<unsigned long long>(options.maxPixels)));
  }
  return s;
}

int runLray(int argc, const char *const *argv) {
  ParseResult parsed = parseOptions(argc, argv);
  if (!parsed.options) {
    std::fputs(parsed.message.c_str(), parsed.exitCode == 0 ? stdout : stderr);
    if (!parsed.message.empty() && parsed.message.back() != '\n')
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
    std::fprintf(stderr, "lray: error: %s\n", e.what());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "lray: error: %s: %s: %s\n", parsed.options->scenePath.c_str(),
                 gActivity.c_str(), describeUnexpectedError(e).c_str());
  } catch (...) {
    std::fprintf(stderr, "lray: error: %s: %s: an unknown error\n",
                 parsed.options->scenePath.c_str(), gActivity.c_str());
  }
  return 1;
}

} // namespace lray
