// Pipeline: run. What one run of lray renders, built once from the options
// and the scene's scene_info: the frames, their size and sampling, the
// backend and integrator, the output files. Its one list of settings
// (settings()) is what --info and --stats print and what a tile's
// fingerprint is made of, so a new setting is described in one place.
#pragma once

#include "render/backends.h"
#include "render/frame_settings.h"
#include "render/image_writer.h"
#include "run/options.h"
#include "scene/scene.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lray {

/// One setting of a run: its name as --info and --stats print it, its
/// value as JSON, and whether it can change a pixel (then it is part of
/// the fingerprint that tells tiles of different renders apart).
struct PlanSetting {
  std::string name;
  std::string json;
  bool changesPixels = true;
};

struct RunPlan {
  std::string scenePath;
  std::string outDir;
  std::string stem; ///< the scene file's name without its extension
  SceneInfo info;   ///< scene_info with the command line's overrides
  FrameSettings frameSettings; ///< sampling, seed, integrator and the window (crop)
  BackendKind backend = BackendKind::Embree;
  int threads = 0; ///< 0: all cores
  ImageFormat format = ImageFormat::Png;
  bool linear = false;
  int firstFrame = 0, lastFrame = 0, frameStep = 1;
  std::optional<std::pair<int, int>> tile; ///< --tile I/N

  /// A window of each frame is rendered and written as a tile.
  bool tiled() const { return !frameSettings.crop.empty(); }
  /// The frames rendered, in order.
  std::vector<int> frames() const;
  /// The frame's image, relative to outDir: <stem>.<ext> for one frame,
  /// <stem>NNNN.<ext> for an animation.
  std::string finalName(int frame) const;
  /// What a render of the frame writes: the final image, or the tile (or
  /// crop) file when tiled().
  std::string outputName(int frame) const;

  /// Every setting, each once, in a fixed order.
  std::vector<PlanSetting> settings() const;
  /// settings() as one JSON object.
  std::string settingsJson() const;
  /// The tiles' fingerprint of the render: the scene file's bytes and every
  /// setting that changes pixels.
  std::string fingerprint(const std::string &sceneBytes) const;
};

/// The plan for `options` over a script whose scene_info is `fromScript`.
/// Throws SceneError for what the two together do not allow (sizes above
/// --max-pixels, a frame range past the last frame, a crop outside the
/// frame, more tiles than tile rows, contradictory sampling options).
RunPlan makeRunPlan(const Options &options, const SceneInfo &fromScript);

/// --info: the plan as one line of JSON: frames, size, sampling, tile rows,
/// clock range, settings, the fingerprint, and each planned frame's output
/// file (with `tiles`, the file names of that many tiles of it).
std::string infoJson(const RunPlan &plan, const std::string &sceneBytes,
                     std::optional<int> tiles);

/// The file name of frame `frame` of `frameCount` for a scene of file name
/// stem `stem` (RunPlan::finalName).
std::string frameFileName(const std::string &stem, int frame, int frameCount, ImageFormat format);

} // namespace lray
