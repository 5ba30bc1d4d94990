// Pipeline: scene description. A user's mistake (bad script, bad value,
// bad file) is a SceneError carrying where it happened; a programmer's
// mistake is an assert.
#pragma once

#include <stdexcept>
#include <string>

namespace lray {

/// Where a scene object was defined: script file and line (line 0 = unknown).
struct SourceLocation {
  std::string file;
  int line = 0;

  /// "file:line" or "file" or "" as available.
  std::string str() const {
    if (file.empty()) return line > 0 ? "line " + std::to_string(line) : std::string();
    return line > 0 ? file + ":" + std::to_string(line) : file;
  }
};

/// An error in the user's input. what() is the complete one-paragraph message,
/// already prefixed with the location when one is known.
class SceneError : public std::runtime_error {
public:
  explicit SceneError(const std::string &message) : std::runtime_error(message) {}
  SceneError(const SourceLocation &loc, const std::string &message)
      : std::runtime_error(loc.str().empty() ? message : loc.str() + ": " + message) {}
};

} // namespace lray
