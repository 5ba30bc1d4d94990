// Pipeline: script -> scene description. The one entry point the render
// loop uses: load a scene file once, then ask it for each frame's Scene in
// the plain model. No Lua type appears in this header.
#pragma once

#include "scene/scene.h"
#include "scene/scene_checks.h"
#include "util/memory_budget.h"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lray {

/// The default cap on the memory a script's Lua state may use: 2 GiB.
inline constexpr uint64_t kDefaultScriptMemory = uint64_t{2} << 30;

struct ScriptOptions {
  bool unsafe = false;          ///< lift the sandbox (--unsafe)
  double timeoutSeconds = 60;   ///< --script-timeout; <= 0 means no limit. Applies to the
                                ///< initial run and to each scene(clock) call separately.
  uint64_t maxPixels = kDefaultMaxPixels; ///< --max-pixels: cap on width*height*samples^2
  uint64_t maxLightSamples = kDefaultMaxLightSamples; ///< --max-light-samples, per light
  uint64_t memoryLimitBytes = kDefaultScriptMemory;   ///< --script-memory; 0: no limit
  /// --render-memory: what one frame's model, textures and acceleration
  /// structure may take (util/memory_budget.h); 0: no limit.
  uint64_t renderMemoryBytes = defaultRenderMemory();
  /// --allow-read: folders a sandboxed script may read besides its own.
  std::vector<std::string> allowRead;
  /// --max-file-size: the largest scene or OBJ file read (text formats
  /// are read whole before they are parsed).
  uint64_t maxFileBytes = uint64_t{1} << 30;
  /// If set, the list the script's read log keeps its files in (the one
  /// list filesRead() copies, shared, not a second copy): for a caller that
  /// wants it past the script's end. ScriptLoadError also carries it.
  std::shared_ptr<std::vector<std::string>> readLog;
};

/// A scene script that failed to load: the SceneError's message, and the
/// files it read before it failed (SceneScript::filesRead()), so that
/// `lray --watch` watches an included file that has an error.
class ScriptLoadError : public SceneError {
public:
  ScriptLoadError(const std::string &message, std::vector<std::string> files)
      : SceneError(message), filesRead(std::move(files)) {}
  std::vector<std::string> filesRead;
};

/// A loaded scene script (lua/README.md, "The scene file"). Not thread-safe; used by one
/// thread.
class SceneScript {
public:
  /// Loads and runs the scene file; relative paths inside the script (images,
  /// OBJ, io.open) resolve against the script's folder. Throws SceneError with
  /// "file:line: message" (plus a Lua traceback for runtime errors): a
  /// ScriptLoadError once the script has started to run.
  explicit SceneScript(const std::string &path, ScriptOptions options = {});
  /// Same from source text; `chunkName` names it in messages, `baseDir`
  /// resolves relative paths (for tests).
  static SceneScript fromString(const std::string &source, const std::string &chunkName,
                                const std::string &baseDir = ".", ScriptOptions options = {});
  SceneScript(SceneScript &&) noexcept;
  SceneScript &operator=(SceneScript &&) noexcept;
  ~SceneScript();

  /// From the global scene_info (defaults if absent), validated (positive
  /// sizes, width*height*samples^2 <= maxPixels).
  const SceneInfo &info() const;

  /// Calls scene(clock) and converts the returned Scene into the plain model.
  /// Throws SceneError (message + traceback); the Lua state is not touched
  /// after this returns.
  Scene buildFrame(double clock);

  /// Warnings from the last buildFrame (e.g. camera aspect vs image aspect).
  const std::vector<std::string> &warnings() const;

  /// The files the script has read so far through the sandbox (dofile,
  /// loadfile, require, io.open, mesh_from_obj, ImagePigment2D), absolute,
  /// once each; not the scene file itself. With --unsafe, io.open is not
  /// seen.
  std::vector<std::string> filesRead() const;

  struct Impl;

private:
  SceneScript(const std::string &source, const std::string &chunkName, const std::string &baseDir,
              ScriptOptions options, bool);
  /// Runs the script and reads scene_info and scene (the constructor's work).
  void load(const std::string &source, const std::string &chunkName);
  std::unique_ptr<Impl> impl_;
};

} // namespace lray
