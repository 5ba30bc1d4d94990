// Pipeline: scene description. Checks on a converted scene that the script
// layer and the command line (after --width/--height/--samples overrides)
// both apply.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <optional>
#include <string>

namespace lray {

/// Default cap on image_width * image_height * samples^2 (--max-pixels; the
/// CLI default in src/run/options.h is the same 1e9).
inline constexpr uint64_t kDefaultMaxPixels = 1000000000;

/// Default cap on one light's shadow rays per shading point
/// (--max-light-samples): a 256 x 256 area light.
inline constexpr uint64_t kDefaultMaxLightSamples = 65536;

/// Throws SceneError at the light's script line when a light would trace
/// more than maxLightSamples shadow rays per shading point (a 100000 x
/// 100000 area light renders for days); the message names the flag.
void validateLightWork(const Scene &scene, uint64_t maxLightSamples);

/// Throws SceneError("<name>: N bytes, more than the limit of M<kind> (raise
/// it with --max-file-size)") when the file at `path` is larger than
/// `maxBytes`: text formats are read whole before they are parsed. `kind`
/// is "" or, say, " for a scene file". A file whose size cannot be read
/// passes (opening it reports the problem).
void checkFileSize(const std::string &path, const std::string &name, uint64_t maxBytes,
                   const char *kind = "");

/// Throws SceneError (prefixed with `where`, e.g. the script name) when a
/// size is not a positive integer, the clocks are not finite, or
/// width * height * samples^2 exceeds maxPixels.
void validateSceneInfo(const SceneInfo &info, uint64_t maxPixels, const std::string &where);

/// The warning when the camera aspect differs from the image's by
/// more than 1 %, else nothing.
std::optional<std::string> aspectWarning(const SceneInfo &info, const Camera &camera);

} // namespace lray
