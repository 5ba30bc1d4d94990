// Pipeline: script -> scene description. The files a scene script has read
// (scripts, OBJ files, images, io.open), in order, once each: what
// `lray --watch` watches. BindingContext holds the one ReadLog of a state;
// SceneScript::filesRead() and ScriptLoadError give it out.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lray::lua {

class ReadLog {
public:
  /// `files`: where the list is kept, shared with a caller that wants it
  /// past the state's end (ScriptOptions::readLog); null: a list of its own.
  explicit ReadLog(std::shared_ptr<std::vector<std::string>> files = nullptr)
      : files_(files ? std::move(files) : std::make_shared<std::vector<std::string>>()) {}

  /// Adds `path` (absolute) unless it is there already.
  void note(const std::string &path) {
    if (std::find(files_->begin(), files_->end(), path) == files_->end()) files_->push_back(path);
  }
  const std::vector<std::string> &files() const { return *files_; }

private:
  std::shared_ptr<std::vector<std::string>> files_;
};

} // namespace lray::lua
