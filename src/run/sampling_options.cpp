// Pipeline: run. The sampling options: the backend and threads, the
// frame's size and samples over scene_info, and how pixels are sampled
// (README.md, "Quality"); they fill SceneInfo and FrameSettings.
#include "run/sampling_options.h"

#include "render/backends.h"
#include "run/option_group.h"
#include "run/option_text.h"
#include "scene/scene_checks.h"
#include "util/printable_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace lray {

namespace {

class SamplingOptions final : public OptionGroup {
public:
  void add(CLI::App &app, Options &o) override {
    const CLI::Validator positive = option_text::finiteNumber(false);
    const CLI::Validator nonNegative = option_text::finiteNumber(true);
    CLI::App &g = *app.add_option_group("Rendering and sampling");
    std::string names; // "embree (default) or kdtree"
    for (const BackendEntry &b : backends()) {
      backendsByName_.emplace(b.name, b.kind);
      const std::string separator = backendNames_.empty() ? "" : " or ";
      backendNames_ += separator + b.name;
      names += separator + b.name + (separator.empty() ? " (default)" : "");
    }
    // Names are looked up after parsing: CLI11's enum transformer shows its
    // internal mapping in --help and in its error message.
    g.add_option("--backend", backend_, "Acceleration backend: " + names)->type_name("NAME");
    g.add_option("-t,--threads", o.threads, "Render threads (default: all cores)")->check(positive);
    g.add_option("-w,--width", o.width, "Image width in pixels (overrides scene_info)")
        ->check(positive);
    g.add_option("-H,--height", o.height, "Image height in pixels (overrides scene_info)")
        ->check(positive);
    g.add_option("-s,--samples", o.samples,
                 "n: n x n samples per pixel, fixed sampling (overrides scene_info)")
        ->check(positive);
    g.add_option("--noise-threshold", o.noiseThreshold,
                 "Adaptive sampling: passes of samples until each pixel's error estimate is "
                 "below T (e.g. 0.01; 0: fixed n x n sampling; overrides scene_info)")
        ->check(nonNegative);
    g.add_option("--min-samples", o.minSamples,
                 "Adaptive sampling: samples per pixel of the first pass (default 16; 1: the "
                 "pixel centre first, more samples only where it differs from a neighbour)")
        ->check(positive);
    g.add_option("--max-samples", o.maxSamples,
                 "Adaptive sampling: most samples a pixel takes (default 1024)")
        ->check(positive);
    g.add_option("--edge-lattice", o.latticeDepth,
                 "Adaptive sampling, centre first: refine each pixel that differs from a "
                 "neighbour on a lattice of cells down to 2^-DEPTH of a pixel wide, cut where "
                 "their corners differ, instead of by Sobol passes (1 to 5, 4 or 5 usual; 0: "
                 "Sobol; best for opaque surfaces under point lights)")
        ->type_name("DEPTH")
        ->check(CLI::Range(0, 5));
    g.add_flag("--sparse-centres", o.sparseCentres,
               "Adaptive sampling, centre first: trace every other pixel centre of every other "
               "row, and fill each centre between traced ones that agree with their mean "
               "(more are filled the higher the noise threshold; for quick, low-quality "
               "frames)");
    g.add_option("--time-limit", o.timeLimit,
                 "Render each frame progressively for at most SECONDS, then write the best "
                 "image so far")
        ->check(positive);
    g.add_option("--seed", o.seed,
                 "Seed of the random sample stream (default 0): another seed renders "
                 "independent samples of the same picture")
        ->check(CLI::Range(0u, 4294967295u));
    g.add_option("--light-sampling", lightSampling_,
                 "Area lights: 'all' (every sample shades every cell; default for fixed "
                 "sampling) or 'spread' (a pixel's samples share the cells; default for adaptive)")
        ->type_name("MODE");
    g.add_option("--integrator", o.integrator,
                 "Light transport: 'whitted' (the shading equation) or 'path' (a physically "
                 "based path tracer; overrides scene_info)")
        ->type_name("NAME")
        ->check(CLI::IsMember({"whitted", "path"}));
    g.add_option("--max-depth", o.maxDepth,
                 "Path tracing: the most scattering events of a path (default 8; overrides "
                 "scene_info)")
        ->check(positive);
    g.add_option("--clamp", o.clamp,
                 "Path tracing: scale each sample down so that no colour component is above "
                 "VALUE (removes fireflies, darkens what is truly brighter; default: none)")
        ->type_name("VALUE")
        ->check(positive);
    g.add_option("--shutter", o.shutter,
                 "Motion blur: the fraction (0 to 1) of the interval between two frames' clocks "
                 "the shutter is open, from the frame's clock on (overrides scene_info; 0: none)")
        ->type_name("FRACTION")
        ->check(CLI::Range(0.0, 1.0));
    g.add_option("--motion-steps", o.motionSteps,
                 "Motion blur: how many clock values in the open shutter scene(clock) is "
                 "called at, 2 to 16 (default 2; overrides scene_info)")
        ->check(CLI::Range(2, 16));
    g.add_flag("--no-shadow-skips", o.noShadowSkips,
               "Trace every shadow ray, even where nothing lies between a tile and a light "
               "(the same image; for measuring)");
  }

  std::string finish(Options &o) override {
    std::string error;
    if (!backend_.empty())
      error = option_text::lookUp(backend_, backendsByName_, "--backend", backendNames_, o.backend);
    if (!error.empty()) return error;
    if (!lightSampling_.empty()) {
      const std::map<std::string, LightSampling> modes{{"all", LightSampling::All},
                                                       {"spread", LightSampling::Spread}};
      LightSampling mode{};
      error = option_text::lookUp(lightSampling_, modes, "--light-sampling", "all or spread", mode);
      if (!error.empty()) return error;
      o.lightSampling = mode;
    }
    if (o.samples && (o.noiseThreshold.value_or(0) > 0 || o.timeLimit > 0))
      return "--samples sets fixed n x n sampling; with --noise-threshold or "
             "--time-limit give --min-samples and --max-samples instead";
    if (o.minSamples && o.maxSamples && *o.minSamples > *o.maxSamples)
      return "--min-samples (" + std::to_string(*o.minSamples) + ") is above --max-samples (" +
             std::to_string(*o.maxSamples) + ")";
    return {};
  }

private:
  std::string backend_, lightSampling_;
  std::map<std::string, BackendKind> backendsByName_;
  std::string backendNames_; // "embree or kdtree": for an unknown name
};

} // namespace

std::unique_ptr<OptionGroup> makeSamplingOptions() { return std::make_unique<SamplingOptions>(); }

SceneInfo effectiveSceneInfo(const SceneInfo &fromScript, const Options &options) {
  SceneInfo info = fromScript;
  if (options.width) info.imageWidth = *options.width;
  if (options.height) info.imageHeight = *options.height;
  if (options.samples) info.samples = *options.samples;
  if (options.integrator) info.integrator = *options.integrator;
  if (options.maxDepth) info.maxDepth = *options.maxDepth;
  if (options.shutter) info.shutter = *options.shutter;
  if (options.motionSteps) info.motionSteps = *options.motionSteps;
  validateSceneInfo(info, options.maxPixelCount(), options.scenePath);
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
  a.maxSamples =
      options.maxSamples.value_or(std::max(a.maxSamples, options.minSamples.value_or(0)));
  a.minSamples = options.minSamples.value_or(std::min(a.minSamples, a.maxSamples));
  if (a.minSamples > a.maxSamples)
    throw SceneError(fmt::format("--min-samples ({}) is above --max-samples ({})", a.minSamples,
                                 a.maxSamples));
  // The first pass's samples take the light's shares in pairs (spread
  // sampling: tile_renderer_impl.h), so it is even; 1 is the centre-first
  // pass.
  if (a.minSamples > 1 && a.minSamples % 2 && a.minSamples < a.maxSamples) ++a.minSamples;
  // The options of the centre-first pass: each works by the noise
  // threshold, from the pixel centres (min samples 1, which it implies),
  // and shades its points once each with every light cell, which the path
  // tracer's paths are not. `byThreshold` and `fromCentres` say how.
  auto centreFirstOption = [&](const char *flag, const char *byThreshold,
                               const char *fromCentres) {
    if (threshold <= 0)
      throw SceneError(fmt::format("{} {}: give --noise-threshold", flag, byThreshold));
    if (options.minSamples.value_or(1) != 1)
      throw SceneError(fmt::format("{} {}: it takes --min-samples 1, not {}", flag, fromCentres,
                                   *options.minSamples));
    if (info.integrator == "path")
      throw SceneError(fmt::format(
          "{} applies to the Whitted integrator, not to --integrator path", flag));
    a.minSamples = 1;
  };
  a.latticeDepth = options.latticeDepth.value_or(0);
  if (a.latticeDepth > 0)
    centreFirstOption("--edge-lattice", "refines by the noise threshold",
                      "starts from the pixel centres");
  a.sparseCentres = options.sparseCentres;
  if (a.sparseCentres)
    centreFirstOption("--sparse-centres", "fills by the noise threshold",
                      "is a centre-first pass");
  s.aovs = options.aovs;
  s.seed = options.seed;
  s.integrator = info.integrator == "path" ? IntegratorKind::Path : IntegratorKind::Whitted;
  s.maxDepth = info.maxDepth;
  s.clamp = options.clamp.value_or(0);
  s.shadowSkips = !options.noShadowSkips;
  s.lightSampling =
      options.lightSampling.value_or(s.adaptive ? LightSampling::Spread : LightSampling::All);
  if (s.adaptive) {
    // An edge lattice's pixel takes at most its whole lattice's points.
    const bool lattice = a.latticeDepth > 0;
    const long double perPixel = lattice ? std::pow((1 << a.latticeDepth) + 1.0L, 2) : a.maxSamples;
    const long double work =
        static_cast<long double>(info.imageWidth) * info.imageHeight * perPixel;
    if (work > static_cast<long double>(options.maxPixelCount()))
      throw SceneError(fmt::format(
          "{}: image_width * image_height * {} = {} exceeds the limit of {} (lower {} or raise "
          "--max-pixels)",
          options.scenePath, lattice ? "lattice points a pixel" : "max samples",
          readableCount(work), readableCount(options.maxPixelCount()),
          lattice ? "--edge-lattice" : "--max-samples"));
  }

  return s;
}

} // namespace lray
