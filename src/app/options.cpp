// Pipeline: application. Command-line parsing with CLI11.
#include "app/options.h"

#include <cmath>

#include <CLI/CLI.hpp>

#include <cctype>
#include <map>
#include <optional>

namespace lray {

namespace {

const char *kDescription =
    "LRay renders a scene written as a Lua script.\n\n"
    "Every frame of <scene.lua> is rendered into <outdir> (created if missing) as\n"
    "<stem>.png for a one-frame scene, or <stem>0000.png, <stem>0001.png, ... for an\n"
    "animation. Paths inside the script are relative to the script's folder.\n\n"
    "Examples:\n"
    "  lray scenes/ring.lua out/                      render all 20 frames\n"
    "  lray scenes/ring.lua out/ --frames 5:5 -w 320  frame 5 only, 320 px wide\n"
    "  lray scene.lua out/ --backend kdtree --stats stats.json\n";

} // namespace

ParseResult parseOptions(int argc, const char *const *argv) {
  Options o;
  CLI::App app(kDescription, "lray");
  // CLI11's PositiveNumber reports its range with 309 digits of DBL_MAX.
  auto finiteNumber = [](bool zeroAllowed) {
    return CLI::Validator(
        [zeroAllowed](std::string &input) -> std::string {
          size_t used = 0;
          double v = -1;
          try {
            v = std::stod(input, &used);
          } catch (const std::exception &) {
            used = 0;
          }
          if (used != input.size() || !std::isfinite(v) || v < 0 || (v == 0 && !zeroAllowed))
            return std::string(zeroAllowed ? "expects a number >= 0" : "expects a positive number") +
                   ", got '" + input + "'";
          return {};
        },
        zeroAllowed ? "NUMBER" : "POSITIVE");
  };
  const CLI::Validator positive = finiteNumber(false), nonNegative = finiteNumber(true);
  app.set_version_flag("--version", std::string("lray ") + LRAY_VERSION);
  app.add_option("scene", o.scenePath, "Scene script (.lua)")->required();
  app.add_option("outdir", o.outDir, "Folder for the rendered images (optional with --watch)");
  app.add_flag("--info", o.info,
               "Load the scene and print its frame count, size and sampling as one line of "
               "JSON (with the overrides given), render nothing; no outdir needed");
  app.add_flag("--watch", o.watch,
               "Live preview: render progressively, and again whenever the scene or a file it "
               "read changes; the image goes to <outdir> (if given) and to the page of --serve");
  auto *serve = app.add_option("--serve", o.serve,
                               "With --watch: serve the preview page at HOST:PORT (default "
                               "127.0.0.1:8765, loopback only)")
                    ->type_name("HOST:PORT")
                    ->expected(0, 1);

  std::map<std::string, BackendKind> byName;
  std::string backendNames; // "embree or kdtree": for an unknown name
  std::string names; // "embree (default) or kdtree": for --help
  for (const BackendEntry &b : backends()) {
    byName.emplace(b.name, b.kind);
    const std::string separator = backendNames.empty() ? "" : " or ";
    backendNames += separator + b.name;
    names += separator + b.name + (separator.empty() ? " (default)" : "");
  }
  // Names are looked up after parsing: CLI11's enum transformer shows its
  // internal mapping in --help and in its error message.
  std::string backend, format;
  app.add_option("--backend", backend, "Acceleration backend: " + names)->type_name("NAME");
  app.add_option("-t,--threads", o.threads, "Render threads (default: all cores)")
      ->check(positive);
  std::string frames;
  app.add_option("--frames", frames,
                 "Render frames A to B inclusive, numbered from 0 as in the file names "
                 "(A:B, A:B:STEP for every STEP-th, or A for one frame)");
  app.add_flag("--skip-existing", o.skipExisting,
               "Do not render a frame (or tile) whose output file already exists as a "
               "complete image of the right size: resume an interrupted animation");
  std::string tile, crop;
  app.add_option("--tile", tile,
                 "Render only band I (0-based) of N bands of rows of each frame, written as "
                 "<frame>.tile-I-of-N.exr; lray-merge stitches the bands into the frame")
      ->type_name("I/N");
  app.add_option("--crop", crop,
                 "Render only the pixels x0 <= x < x1, y0 <= y < y1 of each frame, written as "
                 "<frame>.crop-x0-y0-x1-y1.exr (the general form of --tile)")
      ->type_name("x0:y0:x1:y1");
  app.add_option("-w,--width", o.width, "Image width in pixels (overrides scene_info)")
      ->check(positive);
  app.add_option("-H,--height", o.height, "Image height in pixels (overrides scene_info)")
      ->check(positive);
  app.add_option("-s,--samples", o.samples,
                 "n: n x n samples per pixel, fixed sampling (overrides scene_info)")
      ->check(positive);
  app.add_option("--noise-threshold", o.noiseThreshold,
                 "Adaptive sampling: passes of samples until each pixel's error estimate is "
                 "below T (e.g. 0.01; 0: fixed n x n sampling; overrides scene_info)")
      ->check(nonNegative);
  app.add_option("--min-samples", o.minSamples,
                 "Adaptive sampling: samples per pixel of the first pass (default 16; 1: the "
                 "pixel centre first, more samples only where it differs from a neighbour)")
      ->check(positive);
  app.add_option("--max-samples", o.maxSamples,
                 "Adaptive sampling: most samples a pixel takes (default 1024)")
      ->check(positive);
  app.add_option("--time-limit", o.timeLimit,
                 "Render each frame progressively for at most SECONDS, then write the best "
                 "image so far")
      ->check(positive);
  app.add_option("--seed", o.seed,
                 "Seed of the random sample stream (default 0): another seed renders "
                 "independent samples of the same picture")
      ->check(CLI::Range(0u, 4294967295u));
  std::string lightSampling;
  app.add_option("--light-sampling", lightSampling,
                 "Area lights: 'all' (every sample shades every cell; default for fixed "
                 "sampling) or 'spread' (a pixel's samples share the cells; default for adaptive)")
      ->type_name("MODE");
  std::map<std::string, ImageFormat> formats{
      {"png", ImageFormat::Png}, {"tga", ImageFormat::Tga}, {"exr", ImageFormat::Exr}};
  app.add_option("-f,--format", format, "Output format: png (default), tga or exr")
      ->type_name("FORMAT");
  app.add_flag("--linear", o.linear,
               "Linear workflow: decode 8-bit textures from sRGB, encode 8-bit outputs to sRGB");
  app.add_flag("--aovs", o.aovs,
               "EXR output: add depth (Z), normal (N.X/N.Y/N.Z) and albedo "
               "(Albedo.R/G/B) layers for denoisers and compositors");
  app.add_flag("--no-shadow-skips", o.noShadowSkips,
               "Trace every shadow ray, even where nothing lies between a tile and a light "
               "(the same image; for measuring)");
  app.add_flag("-q,--quiet", o.quiet, "No progress bar or informational output");
  app.add_option("--stats", o.statsPath,
                 "Write render statistics as JSON to FILE (times, rays by kind, memory)");
  app.add_flag("--unsafe", o.unsafe,
               "Give the script the full Lua standard library (os, io write access)");
  app.add_option("--script-timeout", o.scriptTimeout,
                 "Abort a script that runs longer than SECONDS (default 60)")
      ->check(positive);
  app.add_option("--allow-read", o.allowRead,
                 "Let the script read files below DIR too (repeatable; by default only below "
                 "the scene's folder)")
      ->type_name("DIR");
  std::string maxFileSize;
  app.add_option("--max-file-size", maxFileSize,
                 "Refuse a scene or OBJ file larger than SIZE (bytes, or with K, M or G; "
                 "default 1G)")
      ->type_name("SIZE");
  std::string scriptMemory;
  app.add_option("--script-memory", scriptMemory,
                 "Stop a script whose Lua memory grows past SIZE (bytes, or with K, M or G; "
                 "default 2G)")
      ->type_name("SIZE");
  app.add_option("--max-light-samples", o.maxLightSamples,
                 "Refuse a light with more shadow rays per shading point (rows*cols) than "
                 "this (default 65536)")
      ->check(positive);
  app.add_option("--max-pixels", o.maxPixels,
                 "Refuse renders with width*height*samples^2 above this (default 1e9)")
      ->check(positive);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &) {
    return {std::nullopt, 0, app.help()};
  } catch (const CLI::CallForVersion &) {
    return {std::nullopt, 0, std::string("lray ") + LRAY_VERSION + "\n"};
  } catch (const CLI::ParseError &e) {
    return {std::nullopt, 2, "lray: error: " + std::string(e.what()) + " (run 'lray --help' for usage)"};
  }
  auto usageError0 = [](const std::string &why) {
    return ParseResult{std::nullopt, 2, "lray: error: " + why + " (run 'lray --help' for usage)"};
  };

  if (serve->count() > 0 && o.serve.empty()) o.serve = "127.0.0.1:8765";
  if (!o.serve.empty()) {
    if (!o.watch) return usageError0("--serve shows the live preview of --watch: give --watch too");
    const size_t colon = o.serve.rfind(':');
    const std::string port = colon == std::string::npos ? "" : o.serve.substr(colon + 1);
    if (colon == std::string::npos || colon == 0 || port.empty() || port.size() > 5 ||
        port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) > 65535)
      return usageError0("--serve '" + o.serve + "': expected HOST:PORT, e.g. 127.0.0.1:8765");
    o.serveHost = o.serve.substr(0, colon);
    if (o.serveHost.size() > 2 && o.serveHost.front() == '[' && o.serveHost.back() == ']')
      o.serveHost = o.serveHost.substr(1, o.serveHost.size() - 2);
    o.servePort = std::stoi(port);
  }
  if (o.outDir.empty() && !o.watch && !o.info)
    return usageError0("give the folder for the images: lray <scene.lua> <outdir>");

  // A name given in any case; an unknown one lists the known ones.
  auto lookUp = [](std::string text, const auto &table, const char *option, const char *known,
                   auto &out) -> std::optional<ParseResult> {
    for (char &c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto it = table.find(text);
    if (it == table.end())
      return ParseResult{std::nullopt, 2,
                         std::string("lray: error: ") + option + ": unknown value '" + text +
                             "' (expected " + known + "; run 'lray --help' for usage)"};
    out = it->second;
    return std::nullopt;
  };
  if (!backend.empty()) {
    if (auto error = lookUp(backend, byName, "--backend", backendNames.c_str(), o.backend))
      return *error;
  }
  if (!format.empty()) {
    if (auto error = lookUp(format, formats, "--format", "png, tga or exr", o.format))
      return *error;
  }

  // A positive whole number of bytes, or of KiB, MiB or GiB.
  auto parseSize = [](const std::string &text, const char *option,
                      uint64_t &out) -> std::optional<ParseResult> {
    size_t used = 0;
    unsigned long long n = 0;
    try {
      if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0])))
        n = std::stoull(text, &used);
    } catch (const std::exception &) {
      used = 0;
    }
    const std::string unit = used ? text.substr(used) : "";
    const std::map<std::string, int> shifts{{"", 0},  {"K", 10}, {"M", 20}, {"G", 30},
                                            {"k", 10}, {"m", 20}, {"g", 30}};
    auto shift = shifts.find(unit);
    if (!used || n == 0 || shift == shifts.end() || n > (~0ull >> (shift->second + 1)))
      return ParseResult{std::nullopt, 2,
                         std::string("lray: error: ") + option +
                             ": expects a size such as 512M or 4G, got '" + text +
                             "' (run 'lray --help' for usage)"};
    out = static_cast<uint64_t>(n) << shift->second;
    return std::nullopt;
  };
  if (!scriptMemory.empty())
    if (auto error = parseSize(scriptMemory, "--script-memory", o.scriptMemory)) return *error;
  if (!maxFileSize.empty())
    if (auto error = parseSize(maxFileSize, "--max-file-size", o.maxFileBytes)) return *error;
  if (!lightSampling.empty()) {
    const std::map<std::string, LightSampling> modes{{"all", LightSampling::All},
                                                     {"spread", LightSampling::Spread}};
    LightSampling mode{};
    if (auto error = lookUp(lightSampling, modes, "--light-sampling", "all or spread", mode))
      return *error;
    o.lightSampling = mode;
  }
  auto usageError = [](const std::string &why) {
    return ParseResult{std::nullopt, 2, "lray: error: " + why + " (run 'lray --help' for usage)"};
  };
  if (o.samples && (o.noiseThreshold.value_or(0) > 0 || o.timeLimit > 0))
    return usageError("--samples sets fixed n x n sampling; with --noise-threshold or "
                      "--time-limit give --min-samples and --max-samples instead");
  if (o.minSamples && o.maxSamples && *o.minSamples > *o.maxSamples)
    return usageError("--min-samples (" + std::to_string(*o.minSamples) +
                      ") is above --max-samples (" + std::to_string(*o.maxSamples) + ")");

  if (o.aovs && o.format != ImageFormat::Exr)
    return usageError("--aovs needs EXR output (--format exr): PNG and TGA hold only RGB");

  // Non-negative integers separated by `separator`, e.g. "3:9:2" or "1/4".
  auto numbers = [](const std::string &text, char separator, std::vector<int> &out) {
    out.clear();
    size_t start = 0;
    for (;;) {
      size_t end = text.find(separator, start);
      std::string part = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
      if (part.empty() || part.size() > 9 || part.find_first_not_of("0123456789") != std::string::npos)
        return false;
      out.push_back(std::stoi(part));
      if (end == std::string::npos) return true;
      start = end + 1;
    }
  };
  auto usageOf = [](const char *option, const std::string &value, const std::string &why) {
    return ParseResult{std::nullopt, 2, std::string("lray: error: ") + option + " '" + value +
                                            "': " + why + " (run 'lray --help' for usage)"};
  };
  std::vector<int> n;
  if (!frames.empty()) {
    // "A", "A:B" or "A:B:STEP": non-negative integers, 0-based.
    if (!numbers(frames, ':', n) || n.size() > 3)
      return usageOf("--frames", frames, "expected A:B, A:B:STEP or A (0-based frame numbers)");
    const int a = n[0], b = n.size() > 1 ? n[1] : n[0];
    if (b < a)
      return usageOf("--frames", frames,
                     "the last frame (" + std::to_string(b) + ") comes before the first (" +
                         std::to_string(a) + ")");
    if (n.size() == 3 && n[2] == 0) return usageOf("--frames", frames, "the step must be 1 or more");
    o.firstFrame = a;
    o.lastFrame = b;
    o.frameStep = n.size() == 3 ? n[2] : 1;
  }
  if (!tile.empty()) {
    if (!numbers(tile, '/', n) || n.size() != 2)
      return usageOf("--tile", tile, "expected I/N, tile I (0-based) of N");
    if (n[1] == 0 || n[0] >= n[1])
      return usageOf("--tile", tile, "I must be below N (tiles are numbered from 0)");
    o.tile = std::pair<int, int>(n[0], n[1]);
  }
  if (!crop.empty()) {
    if (!numbers(crop, ':', n) || n.size() != 4)
      return usageOf("--crop", crop, "expected x0:y0:x1:y1, pixel coordinates");
    if (n[2] <= n[0] || n[3] <= n[1])
      return usageOf("--crop", crop, "the window is empty (x1 must be above x0, y1 above y0)");
    o.crop = PixelWindow{n[0], n[1], n[2], n[3]};
  }
  if (o.tile && o.crop) return usageError("--tile and --crop both choose the pixels: give one");
  if (o.watch && (o.tile || o.crop || o.info || o.skipExisting || o.timeLimit > 0))
    return usageError("--watch renders whole frames until the scene changes: --tile, --crop, "
                      "--info, --skip-existing and --time-limit do not apply to it");
  return {o, 0, ""};
}

} // namespace lray
