// Pipeline: script -> scene description. What a sandboxed scene script may
// do (lua/README.md, "The sandbox"): read below its own folder and those of
// --allow-read only, read files up to --max-file-size, use up to
// --script-memory, and run until its deadline (--script-timeout).
// BindingContext holds one; sandbox.cpp's library wrappers and the binding
// code that reads files or allocates ask it.
#pragma once

#include "bindings/lua_allocator.h"

#include <lua.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lray::lua {

class SandboxPolicy {
public:
  explicit SandboxPolicy(std::string baseDirectory) : baseDir(std::move(baseDirectory)) {}

  /// Path of `file` resolved against the script folder.
  std::string resolvePath(const std::string &file) const;
  /// resolvePath for a file the script reads: throws ScriptError, naming
  /// `what` and the path, when it lies outside every folder of readRoots
  /// (after symbolic links are followed), or exists and is not a regular
  /// file.
  std::string readablePath(const std::string &file, const char *what) const;

  /// Throws ScriptError naming `what` when the script's memory, Lua heap and
  /// external together, is past --script-memory even after a full garbage
  /// collection (what Lua does before it refuses an allocation). Only from
  /// binding code, whose objects in use are on the Lua stack.
  void checkMemory(lua_State *L, const char *what) const;
  /// Whether the script's memory is past the limit after a full collection.
  bool pastMemoryLimit(lua_State *L) const;

  /// The script's folder: relative paths resolve against it.
  std::string baseDir;
  /// The folders a sandboxed script may read below (canonical): the scene's
  /// folder and those of --allow-read. Empty: anywhere (--unsafe).
  std::vector<std::filesystem::path> readRoots;
  /// --max-file-size: the largest OBJ file mesh_from_obj reads.
  uint64_t maxFileBytes = uint64_t{1} << 30;
  /// The state's allocator (set by ScriptState): its limit and the pool of
  /// memory held outside the Lua heap (external_memory.h).
  LuaAllocator *allocator = nullptr;
  /// When the running call must stop (max: no call is running).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  /// --script-timeout, per call; <= 0: none.
  double timeoutSeconds = 0;
};

} // namespace lray::lua
