// Pipeline: application. The whole `lray` program behind a thin main():
// parse options, run the script, then per frame build the scene model,
// the backend and the image, and write it atomically.
#pragma once

#include "app/options.h"
#include "bindings/scene_script.h"
#include "scene/scene.h"

#include <string>

namespace lray {

/// Runs lray; returns the process exit status (0 ok, 1 render or scene
/// error, 2 usage error). Errors are printed to stderr as one paragraph.
int runLray(int argc, const char *const *argv);

/// The last-resort handler's account of an exception that is not a
/// SceneError (a bug or a resource failure): readable, with no C++ library
/// names ("out of memory", not "std::bad_alloc").
std::string describeUnexpectedError(const std::exception &e);

/// The script limits and sandbox the options ask for.
ScriptOptions scriptOptionsOf(const Options &options);

/// File name of frame `frame` of a scene: <stem>.<ext> for one frame,
/// <stem>NNNN.<ext> for an animation.
std::string frameFileName(const std::string &stem, int frame, int frameCount, ImageFormat format);

/// Applies the command-line overrides to scene_info and checks the result
/// (positive sizes, the --max-pixels cap, the frame range). Throws SceneError.
SceneInfo effectiveSceneInfo(const SceneInfo &fromScript, const Options &options);

/// How pixels are sampled, from the options and scene_info: adaptive when a
/// noise threshold or a time limit is given, with its sample bounds and
/// light sampling. Throws SceneError on a contradiction (e.g. --max-samples
/// without adaptive sampling) or work above --max-pixels.
FrameSettings samplingSettings(const SceneInfo &info, const Options &options);

} // namespace lray
