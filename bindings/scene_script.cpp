// Pipeline: script -> scene description. See scene_script.h.
#include "bindings/scene_script.h"

#include "bindings/scene_converter.h"
#include "bindings/script_state.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace lray {

struct SceneScript::Impl {
  Impl(const std::string &baseDir, const ScriptOptions &opts)
      : state(baseDir, opts), options(opts) {}
  lua::ScriptState state;
  ScriptOptions options;
  std::string displayName;
  SceneInfo info;
  std::vector<std::string> warnings;
};

namespace {

std::string readScript(const std::string &path, uint64_t maxBytes) {
  checkFileSize(path, path, maxBytes, " for a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Pushes the global `name`, read raw: a script may give _G a metatable,
/// whose __index must not run (or fail, or loop) outside any protected call
/// and time limit. Allocates: only inside ScriptState::protectedCall.
void pushRawGlobal(lua_State *L, const char *name) {
  lua_rawgeti(L, LUA_REGISTRYINDEX, LUA_RIDX_GLOBALS);
  lua_pushstring(L, name);
  lua_rawget(L, -2);
  lua_remove(L, -2);
}

/// The global named by the light userdata at index 1 (a C string).
int rawGlobal(lua_State *L) {
  pushRawGlobal(L, static_cast<const char *>(lua_touserdata(L, 1)));
  return 1;
}

/// scene(clock), the function read raw: the clock is at index 1.
int callScene(lua_State *L) {
  pushRawGlobal(L, "scene");
  if (!lua_isfunction(L, -1))
    return luaL_error(L, "the global scene is no longer a function (the script changed it)");
  lua_pushvalue(L, 1);
  lua_call(L, 1, 1);
  return 1;
}

/// Pushes the global `name` (a string literal), read raw in a protected call.
void pushGlobal(lua::ScriptState &state, const char *name) {
  lua_State *L = state.state();
  lua_pushcfunction(L, &rawGlobal); // neither push allocates
  lua_pushlightuserdata(L, const_cast<char *>(name));
  state.protectedCall(1, 1);
}

std::string folderOf(const std::string &path) {
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

} // namespace

SceneScript::SceneScript(const std::string &path, ScriptOptions options)
    : SceneScript(readScript(path, options.maxFileBytes), "@" + path, folderOf(path), options,
                  true) {}

SceneScript SceneScript::fromString(const std::string &source, const std::string &chunkName,
                                    const std::string &baseDir, ScriptOptions options) {
  return SceneScript(source, "=" + chunkName, baseDir, options, true);
}

SceneScript::SceneScript(const std::string &source, const std::string &chunkName,
                         const std::string &baseDir, ScriptOptions options, bool)
    : impl_(std::make_unique<Impl>(baseDir, options)) {
  try {
    load(source, chunkName);
  } catch (const SceneError &e) {
    throw ScriptLoadError(e.what(), filesRead());
  }
}

void SceneScript::load(const std::string &source, const std::string &chunkName) {
  impl_->displayName = chunkName.substr(1);
  lua::ScriptState &state = impl_->state;
  lua_State *L = state.state();
  state.run(source, chunkName);

  SourceLocation where{impl_->displayName, 0};
  pushGlobal(state, "scene_info");
  if (const auto *info = lua::toObject<lua::SceneInfoObj>(L, -1)) {
    impl_->info = *info;
    SourceLocation loc = state.context().resolve(info->loc);
    if (loc.line > 0) where = loc;
  } else if (!lua_isnil(L, -1)) {
    std::string given = lua::typeName(L, -1);
    lua_pop(L, 1);
    throw SceneError(where, "scene_info must be a SceneInfo, got " + given);
  }
  lua_pop(L, 1);
  validateSceneInfo(impl_->info, impl_->options.maxPixels, where.str());

  pushGlobal(state, "scene");
  bool isFunction = lua_isfunction(L, -1);
  lua_pop(L, 1);
  if (!isFunction)
    throw SceneError(SourceLocation{impl_->displayName, 0},
                     "the script must define a global function scene(clock) returning a Scene");
}

SceneScript::SceneScript(SceneScript &&) noexcept = default;
SceneScript &SceneScript::operator=(SceneScript &&) noexcept = default;
SceneScript::~SceneScript() = default;

const SceneInfo &SceneScript::info() const { return impl_->info; }

const std::vector<std::string> &SceneScript::warnings() const { return impl_->warnings; }

std::vector<std::string> SceneScript::filesRead() const {
  return impl_->state.context().readLog.files();
}

Scene SceneScript::buildFrame(double clock) {
  lua::ScriptState &state = impl_->state;
  lua_State *L = state.state();
  impl_->warnings.clear();
  lua_pushcfunction(L, &callScene);
  lua_pushnumber(L, clock);
  state.protectedCall(1, 1);
  const auto *sceneObj = lua::toObject<lua::SceneObj>(L, -1);
  if (!sceneObj) {
    std::string given = lua::typeName(L, -1);
    lua_pop(L, 1);
    throw SceneError(SourceLocation{impl_->displayName, 0},
                     "scene(clock) must return a Scene, got " + given);
  }
  Scene scene;
  try {
    scene = lua::convertScene(*sceneObj, state.context(), impl_->options.renderMemoryBytes);
  } catch (...) {
    lua_pop(L, 1);
    throw;
  }
  // The frame's Lua objects are garbage now. No full collection here: the
  // allocator keeps freed blocks for the next frame anyway, and the next
  // frame's allocations drive the collector.
  lua_pop(L, 1);
  validateLightWork(scene, impl_->options.maxLightSamples);
  if (auto warning = aspectWarning(impl_->info, scene.camera)) impl_->warnings.push_back(*warning);
  return scene;
}

} // namespace lray
