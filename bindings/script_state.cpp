// Pipeline: script -> scene description. See script_state.h.
#include "bindings/script_state.h"

#include "bindings/register_classes.h"
#include "bindings/sandbox.h"

#include <cmath>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace lray::lua {

namespace {

int traceback(lua_State *L) {
  // Past the memory limit the message says all, and building a traceback
  // would only meet the limit again.
  if (const LuaAllocator *allocator = BindingContext::of(L).allocator;
      allocator && allocator->overLimit() && lua_type(L, 1) == LUA_TSTRING)
    return 1;
  const char *message = lua_tostring(L, 1);
  if (!message) {
    if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING) return 1;
    message = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
  }
  luaL_traceback(L, L, message, 1);
  return 1;
}

void timeoutHook(lua_State *L, lua_Debug *) {
  BindingContext &ctx = BindingContext::of(L);
  ctx.lastSeen = ctx.currentLocation(L);
  // Script code runs: no binding call is under way (no binding calls Lua
  // code or anything that could run a metamethod: their table accesses
  // are raw), so a deferral still open was left by a longjmp (a true
  // out-of-memory) and must end.
  if (ctx.allocator) ctx.allocator->clearDeferrals();
  if (std::chrono::steady_clock::now() <= ctx.deadline) return;
  {
    std::string message = "the script ran longer than " + formatNumber(ctx.timeoutSeconds) +
                          " seconds and was stopped (raise the limit with --script-timeout)";
    pushErrorMessage(L, message.c_str());
  } // destroyed before lua_error longjmps
  lua_error(L);
}

// An error outside any protected call is a bug in this layer.
int panic(lua_State *L) {
  std::fprintf(stderr, "lray: unprotected Lua error: %s\n", lua_tostring(L, -1));
  std::abort();
}

// How many VM instructions between deadline checks: cheap, yet a runaway
// loop is stopped within milliseconds of its deadline.
constexpr int kHookInstructions = 10000;

} // namespace

ScriptState::ScriptState(const std::string &baseDir, const ScriptOptions &options)
    : ctx_(std::make_unique<BindingContext>(baseDir.empty() ? std::string(".") : baseDir)) {
  L_ = lua_newstate(&LuaAllocator::allocate, allocator_.get());
  if (!L_) throw SceneError("cannot create a Lua state (out of memory)");
  lua_atpanic(L_, &panic);
  ctx_->attach(L_);
  ctx_->timeoutSeconds = options.timeoutSeconds;
  ctx_->allocator = allocator_.get();
  ctx_->maxFileBytes = options.maxFileBytes;
  ctx_->readLog = ReadLog(options.readLog);
  // Scene scripts make many short-lived values (Vector, Transform):
  // generational collection frees them young and keeps the peak low.
  lua_gc(L_, LUA_GCGEN, 0, 0);
  if (!options.unsafe) {
    namespace fs = std::filesystem;
    std::vector<std::string> roots{ctx_->baseDir};
    roots.insert(roots.end(), options.allowRead.begin(), options.allowRead.end());
    for (const std::string &dir : roots) {
      std::error_code ec;
      fs::path root;
      if (fs::is_directory(dir, ec)) root = fs::canonical(dir, ec);
      // An empty root would be a prefix of every path: refuse, never widen.
      if (ec || root.empty()) {
        lua_close(L_);
        L_ = nullptr;
        throw SceneError("--allow-read: '" + dir + "' is not a folder");
      }
      ctx_->readRoots.push_back(root);
    }
  }
  openLibraries(L_, options.unsafe);
  registerAllClasses(L_);
  // Also without a timeout: the hook notes where the script is.
  lua_sethook(L_, &timeoutHook, LUA_MASKCOUNT, kHookInstructions);
  try {
    run(kPreludeSource, ctx_->preludeSource);
    // The limit is the script's: LRay's own libraries and prelude are set
    // up without it (opening them outside a protected call cannot fail
    // cleanly), then count against it.
    const auto limit = static_cast<size_t>(options.memoryLimitBytes);
    if (limit && allocator_->bytesInUse() >= limit)
      throw SceneError("--script-memory: " + LuaAllocator::formatBytes(limit) +
                       " is less than the memory LRay's own libraries take (" +
                       LuaAllocator::formatBytes(allocator_->bytesInUse()) + ")");
    allocator_->setLimit(limit);
  } catch (...) {
    ctx_->destroyLiveObjects();
    lua_close(L_); // the destructor does not run for a failed constructor
    L_ = nullptr;
    throw;
  }
}

ScriptState::~ScriptState() {
  if (!L_) return;
  // lua_close runs the remaining finalizers. The sandbox lets scripts
  // install none, but with --unsafe one could loop forever; Lua runs them
  // with the hooks off, so only the watchdog can end that.
  armDeadline("its finalizers");
  // The C++ parts of LRay's objects are destroyed here, not by finalizers:
  // Lua 5.4 frees an object whose finalizer an emergency collection at the
  // memory limit postponed without running it (the script fuzzer's leak of
  // a Mesh's arrays). No script code runs after this point in the sandbox.
  ctx_->destroyLiveObjects();
  // Only the time limit applies to what finalizers remain (--unsafe).
  if (allocator_) allocator_->setLimit(0);
  lua_close(L_);
  watchdog_.disarm();
}

void ScriptState::armDeadline(const char *what) {
  if (!(ctx_->timeoutSeconds > 0)) return;
  auto budget = std::chrono::duration<double>(std::min(ctx_->timeoutSeconds, 1e9));
  ctx_->deadline = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(budget);
  watchdog_.arm(ctx_->deadline, chunk_ + ": the script ran longer than " +
                                    formatNumber(ctx_->timeoutSeconds) + " seconds (in " + what +
                                    ") and was stopped (raise the limit with --script-timeout)");
}

void ScriptState::protectedCall(int nargs, int nresults) {
  int handler = lua_gettop(L_) - nargs;
  lua_pushcfunction(L_, &traceback);
  lua_insert(L_, handler);
  armDeadline("a library call");
  ctx_->lastSeen = {};
  allocator_->takeRefused(); // a refusal from an earlier call is not this one's
  allocator_->clearDeferrals();
  int status = lua_pcall(L_, nargs, nresults, handler);
  ctx_->deadline = std::chrono::steady_clock::time_point::max();
  watchdog_.disarm();
  lua_remove(L_, handler);
  if (status != LUA_OK) {
    std::string message = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "unknown Lua error";
    lua_pop(L_, 1);
    if (status == LUA_ERRMEM && allocator_->takeRefused()) {
      // Lua raises memory errors without a position or the message handler.
      const SourceLocation where = ctx_->resolve(ctx_->lastSeen);
      throw SceneError((where.line > 0 ? where.str() : chunk_) + ": " +
                       allocator_->limitMessage());
    }
    throw SceneError(message);
  }
}

void ScriptState::run(const std::string &source, const std::string &chunkName) {
  if (chunkName != ctx_->preludeSource) chunk_ = chunkName.empty() ? "" : chunkName.substr(1);
  if (luaL_loadbufferx(L_, source.data(), source.size(), chunkName.c_str(), "t") != LUA_OK) {
    std::string message = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    // Syntax errors start with the chunk's name; a refused binary chunk
    // does not.
    const std::string name = chunkName.empty() ? "" : chunkName.substr(1);
    if (message.rfind(name, 0) != 0) message = name + ": " + message;
    throw SceneError(message);
  }
  protectedCall(0, 0);
}

} // namespace lray::lua
