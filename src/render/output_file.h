// Pipeline: render (last stage). How every output of LRay (images, tiles,
// --stats) reaches its path: complete or not at all, and never by replacing
// what is not a regular file (README.md, "Security").
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace lray {

/// Writes the output `what` ("image", "tile", "statistics") to `path`:
/// - a regular file, a missing one, or a symbolic link to either (then the
///   link's target) is written under a temporary name beside it (`write`
///   gets that name and returns "" or why it failed) and renamed over it,
///   so the final name never holds a half-written file;
/// - anything else at `path` (a device such as /dev/null, a pipe, a link to
///   one) is written to through `path`, never replaced;
/// - a folder in the way is an error.
/// Throws SceneError "cannot write <what> '<path>': <why>", with the
/// system's reason ("No space left on device"), and leaves no temporary file.
void writeAtomically(const std::string &path, const char *what,
                     const std::function<std::string(const std::string &tmp)> &write);

/// writeAtomically with `bytes` as the file's contents.
void writeOutputFile(const std::string &path, const char *what, std::string_view bytes);

/// Writes `bytes` to the file `path` (created or truncated), checking every
/// write: "" or the system's reason.
std::string writeWholeFile(const std::string &path, std::string_view bytes);

} // namespace lray
