// Pipeline: run. See run_plan.h.
#include "run/run_plan.h"

#include "render/tile_file.h"
#include "run/sampling_options.h"
#include "util/json_string.h"
#include "util/scene_error.h"

#include <fmt/format.h>

#include <filesystem>

namespace lray {

namespace {

std::string number(double v) { return fmt::format("{:.17g}", v); }

} // namespace

std::string frameFileName(const std::string &stem, int frame, int frameCount, ImageFormat format) {
  std::string ext = formatExtension(format);
  if (frameCount <= 1) return stem + "." + ext;
  return fmt::format("{}{:04d}.{}", stem, frame, ext);
}

RunPlan makeRunPlan(const Options &options, const SceneInfo &fromScript) {
  RunPlan plan;
  plan.scenePath = options.scenePath;
  plan.outDir = options.outDir;
  plan.stem = std::filesystem::path(options.scenePath).stem().string();
  plan.info = effectiveSceneInfo(fromScript, options);
  plan.frameSettings = samplingSettings(plan.info, options);
  plan.frameSettings.width = plan.info.imageWidth;
  plan.frameSettings.height = plan.info.imageHeight;
  plan.frameSettings.samples = plan.info.samples;
  plan.backend = options.backend;
  plan.threads = options.threads;
  plan.format = options.format;
  plan.linear = options.linear;
  plan.firstFrame = options.firstFrame.value_or(0);
  plan.lastFrame = options.lastFrame.value_or(plan.info.frames - 1);
  plan.frameStep = options.frameStep;
  plan.tile = options.tile;
  const int width = plan.info.imageWidth, height = plan.info.imageHeight;
  if (options.tile) {
    plan.frameSettings.crop = tileBand(options.tile->first, options.tile->second, width, height);
  } else if (options.crop) {
    const PixelWindow &c = *options.crop;
    if (c.x1 > width || c.y1 > height)
      throw SceneError(
          fmt::format("--crop {}:{}:{}:{}: the window reaches outside the {} x {} frame", c.x0,
                      c.y0, c.x1, c.y1, width, height));
    plan.frameSettings.crop = c;
  }
  return plan;
}

std::vector<int> RunPlan::frames() const {
  std::vector<int> out;
  for (int f = firstFrame; f <= lastFrame; f += frameStep) out.push_back(f);
  return out;
}

std::string RunPlan::finalName(int frame) const {
  return frameFileName(stem, frame, info.frames, format);
}

std::string RunPlan::outputName(int frame) const {
  const std::string name = finalName(frame);
  if (!tiled()) return name;
  return tile ? tileFileName(name, tile->first, tile->second)
              : cropFileName(name, frameSettings.crop);
}

std::vector<PlanSetting> RunPlan::settings() const {
  const AdaptiveSettings &a = frameSettings.adaptiveSettings;
  // The order is the JSON's; a setting that cannot change a pixel says so.
  return {
      {"backend", jsonString(backendName(backend))},
      {"integrator",
       jsonString(frameSettings.integrator == IntegratorKind::Path ? "path" : "whitted")},
      {"max_depth", std::to_string(frameSettings.maxDepth),
       frameSettings.integrator == IntegratorKind::Path},
      {"clamp", number(frameSettings.clamp), frameSettings.integrator == IntegratorKind::Path},
      {"width", std::to_string(info.imageWidth)},
      {"height", std::to_string(info.imageHeight)},
      {"samples", std::to_string(info.samples)},
      {"mode", jsonString(frameSettings.adaptive ? "adaptive" : "fixed")},
      {"noise_threshold", number(a.noiseThreshold)},
      {"min_samples", std::to_string(a.minSamples)},
      {"max_samples", std::to_string(a.maxSamples)},
      {"edge_lattice", std::to_string(a.latticeDepth), a.latticeDepth > 0},
      {"sparse_centres", a.sparseCentres ? "true" : "false", a.sparseCentres},
      {"time_limit", number(a.timeLimit)},
      {"seed", std::to_string(frameSettings.seed)},
      {"light_sampling",
       jsonString(frameSettings.lightSampling == LightSampling::Spread ? "spread" : "all")},
      {"shutter", number(info.shutter)},
      {"motion_steps", std::to_string(info.motionSteps), info.shutter > 0},
      {"format", jsonString(formatExtension(format))},
      {"linear", linear ? "true" : "false"},
      {"aovs", frameSettings.aovs ? "true" : "false"},
      {"shadow_skips", frameSettings.shadowSkips ? "true" : "false", false},
      {"threads", std::to_string(threads), false},
  };
}

std::string RunPlan::settingsJson() const {
  std::string out = "{";
  for (const PlanSetting &s : settings())
    out += (out.size() > 1 ? "," : "") + jsonString(s.name) + ":" + s.json;
  return out + "}";
}

std::string RunPlan::fingerprint(const std::string &sceneBytes) const {
  std::string key;
  for (const PlanSetting &s : settings())
    if (s.changesPixels) key += s.name + "=" + s.json + ";";
  return renderFingerprint(sceneBytes, key);
}

std::string infoJson(const RunPlan &plan, const std::string &sceneBytes, std::optional<int> tiles) {
  const SceneInfo &info = plan.info;
  const int rows = (info.imageHeight + kTileSize - 1) / kTileSize;
  if (tiles && *tiles > rows)
    throw SceneError(fmt::format("--tiles {}: a {} x {} frame has {} rows of {}-pixel tiles, so "
                                 "at most {} tiles",
                                 *tiles, info.imageWidth, info.imageHeight, rows, kTileSize, rows));
  std::string outputs;
  for (int frame : plan.frames()) {
    const std::string name = plan.finalName(frame);
    outputs += fmt::format("{}{{\"frame\":{},\"clock\":{},\"file\":{}", outputs.empty() ? "" : ",",
                           frame, number(info.clockForFrame(frame)), jsonString(name));
    if (tiles) {
      outputs += ",\"tiles\":[";
      for (int i = 0; i < *tiles; ++i)
        outputs += (i ? "," : "") + jsonString(tileFileName(name, i, *tiles));
      outputs += "]";
    }
    outputs += "}";
  }
  return fmt::format("{{\"frames\":{},\"width\":{},\"height\":{},\"samples\":{},\"adaptive\":{},"
                     "\"tile_rows\":{},\"start_clock\":{},\"end_clock\":{},\"settings\":{},"
                     "\"fingerprint\":{},\"outputs\":[{}]}}",
                     info.frames, info.imageWidth, info.imageHeight, info.samples,
                     plan.frameSettings.adaptive ? "true" : "false", rows, number(info.startClock),
                     number(info.endClock), plan.settingsJson(),
                     jsonString(plan.fingerprint(sceneBytes)), outputs);
}

} // namespace lray
