// Pipeline: application. The whole `lray` program behind a thin main():
// parse options, run the script, make the run plan (run/run_plan.h), then
// per frame build the scene model, the backend and the image, and write it
// atomically; or the live preview (app/watch/).
#pragma once

#include <exception>

#include <string>

namespace lray {

/// Runs lray; returns the process exit status (0 ok, 1 render or scene
/// error, 2 usage error). Errors are printed to stderr as one paragraph.
int runLray(int argc, const char *const *argv);

/// The last-resort handler's account of an exception that is not a
/// SceneError (a bug or a resource failure): readable, with no C++ library
/// names ("out of memory", not "std::bad_alloc").
std::string describeUnexpectedError(const std::exception &e);

} // namespace lray
