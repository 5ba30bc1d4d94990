// Pipeline: run. The command line (README.md, "Command line"), parsed into
// plain options; run_plan.h turns them and the scene's scene_info into what
// a run renders. The options are parsed in groups (option_group.h).
#pragma once

#include "render/backends.h"
#include "render/frame_settings.h"
#include "render/image_writer.h"
#include "util/memory_budget.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lray {

/// Everything `lray <scene.lua> <outdir> [options]` can say.
struct Options {
  std::string scenePath;
  std::string outDir;
  BackendKind backend = backends().front().kind;
  int threads = 0; ///< 0 = all cores
  std::optional<int> firstFrame, lastFrame; ///< --frames A:B[:STEP], inclusive, 0-based
  int frameStep = 1;                        ///< --frames A:B:STEP
  bool skipExisting = false; ///< leave frames (and tiles) whose complete image exists
  bool info = false;   ///< --info: print the run plan as JSON, render nothing
  std::optional<int> infoTiles; ///< --tiles N: --info also lists N tile names per frame
  bool watch = false;  ///< --watch: live preview, re-rendering on every save (app/watch/)
  std::string serve;   ///< --serve HOST:PORT ("" = no page); parsed into serveHost/Port
  std::string serveHost;
  int servePort = 0;
  /// --tile I/N: band I (0-based) of N bands of rows; --crop: a pixel window.
  std::optional<std::pair<int, int>> tile;
  std::optional<PixelWindow> crop;
  std::optional<int> width, height, samples;
  std::optional<double> noiseThreshold;       ///< adaptive sampling (0: fixed)
  std::optional<std::string> integrator;      ///< --integrator: "whitted" or "path"
  std::optional<int> maxDepth;                ///< --max-depth
  std::optional<double> shutter;              ///< --shutter
  std::optional<int> motionSteps;             ///< --motion-steps
  std::optional<double> clamp;                ///< --clamp: path samples' largest component
  std::optional<int> minSamples, maxSamples;  ///< adaptive: per pixel
  std::optional<int> latticeDepth;            ///< --edge-lattice: 0 (Sobol) or 1 to 6
  bool sparseCentres = false;                 ///< --sparse-centres
  double timeLimit = 0;                       ///< seconds per frame; 0: none
  uint32_t seed = 0;                          ///< the random stream's seed
  std::optional<LightSampling> lightSampling; ///< default: all (fixed), spread (adaptive)
  ImageFormat format = ImageFormat::Png;
  bool linear = false;
  bool aovs = false; ///< EXR: depth, normal and albedo layers
  bool noShadowSkips = false;
  bool quiet = false;
  bool unsafe = false;
  std::string statsPath;
  double scriptTimeout = 60;
  uint64_t scriptMemory = uint64_t{2} << 30; ///< bytes; --script-memory 512M, 4G, ...
  /// --render-memory: a frame's scene model, textures and acceleration
  /// structure (util/memory_budget.h).
  uint64_t renderMemory = defaultRenderMemory();
  std::vector<std::string> allowRead;        ///< --allow-read DIR (repeatable)
  uint64_t maxFileBytes = uint64_t{1} << 30; ///< --max-file-size: scene and OBJ files
  double maxPixels = 1e9; ///< cap on width * height * samples^2
  /// --max-pixels as a count (any larger value than 2^64 is no cap).
  uint64_t maxPixelCount() const {
    return maxPixels >= 18446744073709549568.0 ? UINT64_MAX : static_cast<uint64_t>(maxPixels);
  }
  double maxLightSamples = 65536; ///< cap on one light's shadow rays per shading point
};

/// The outcome of parsing: either options to run, or an exit code with the
/// text to print (help, version, or a usage error).
struct ParseResult {
  std::optional<Options> options;
  int exitCode = 0;
  std::string message;  ///< printed to stdout when exitCode == 0, else to stderr
};

ParseResult parseOptions(int argc, const char *const *argv);

/// Every option's longest name ("--seed", ...), in --help's order: what the
/// run plan's tests check each option against.
std::vector<std::string> optionNames();

} // namespace lray
