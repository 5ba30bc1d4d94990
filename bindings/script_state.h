// Pipeline: script -> scene description. One prepared lua_State: sandboxed
// libraries, every LRay class, the prelude, the timeout hook and protected
// calls with tracebacks. SceneScript and the binding tests both use it.
#pragma once

#include "bindings/lua_allocator.h"
#include "bindings/lua_binding.h"
#include "bindings/scene_script.h"
#include "bindings/script_watchdog.h"

#include <memory>
#include <string>

namespace lray::lua {

/// The prelude's text (lua/prelude.lua, embedded at build time).
extern const char kPreludeSource[];

class ScriptState {
public:
  ScriptState(const std::string &baseDir, const ScriptOptions &options);
  ~ScriptState();
  ScriptState(const ScriptState &) = delete;
  ScriptState &operator=(const ScriptState &) = delete;

  lua_State *state() const { return L_; }
  BindingContext &context() { return *ctx_; }

  /// Compiles and runs `source` (text only); `chunkName` is Lua's chunk name
  /// ("@path" or "=name"). Throws SceneError: syntax errors as Lua reports
  /// them, runtime errors with a traceback.
  void run(const std::string &source, const std::string &chunkName);

  /// lua_pcall with a traceback handler and the timeout armed; throws
  /// SceneError on error. The function and its arguments are on the stack.
  void protectedCall(int nargs, int nresults);

private:
  std::unique_ptr<LuaAllocator> allocator_ = std::make_unique<LuaAllocator>();
  lua_State *L_ = nullptr;
  std::unique_ptr<BindingContext> ctx_;
  std::string chunk_ = "the script"; ///< the scene's name, for messages without a line
  ScriptWatchdog watchdog_;
  /// Arms the hook's deadline and the watchdog for a call starting now.
  void armDeadline(const char *what);
};

} // namespace lray::lua
