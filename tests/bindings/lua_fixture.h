// Test fixture for the binding layer: runs Lua snippets in a fully prepared
// state (sandbox, classes, prelude) as chunk "test.lua" and reports errors
// as their first line (the message without the traceback).
#pragma once

#include "bindings/scene_converter.h"
#include "bindings/script_state.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace lray::lua {

class LuaFixture : public ::testing::Test {
protected:
  void SetUp() override { reset(); }

  /// Fresh state; `baseDir` resolves relative paths.
  void reset(const std::string &baseDir = LRAY_SOURCE_DIR "/tests/bindings",
             ScriptOptions options = {}) {
    state_.reset();
    // The tests read the gallery's images and models too.
    if (!options.unsafe && options.allowRead.empty())
      options.allowRead.push_back(LRAY_SOURCE_DIR "/scenes");
    state_ = std::make_unique<ScriptState>(baseDir, options);
  }

  /// Runs `code`; returns "" on success, else the error message without its traceback.
  std::string runLua(const std::string &code) {
    try {
      state_->run(code, "=test.lua");
      return "";
    } catch (const SceneError &e) {
      std::string message = e.what();
      return message.substr(0, message.find("\nstack traceback:"));
    }
  }

  /// The full error text (with traceback), or "".
  std::string runLuaFull(const std::string &code) {
    try {
      state_->run(code, "=test.lua");
      return "";
    } catch (const SceneError &e) {
      return e.what();
    }
  }

  /// Evaluates an expression and returns tostring() of the result.
  std::string str(const std::string &expr) {
    std::string error = runLua("__result = tostring(" + expr + ")");
    if (!error.empty()) return "ERROR: " + error;
    return global<std::string>("__result");
  }
  double num(const std::string &expr) {
    std::string error = runLua("__result = " + expr);
    EXPECT_EQ(error, "") << expr;
    return global<double>("__result");
  }
  bool truth(const std::string &expr) {
    std::string error = runLua("__result = (" + expr + ") and true or false");
    EXPECT_EQ(error, "") << expr;
    return global<bool>("__result");
  }

  template <class T> T global(const char *name) {
    lua_State *L = state_->state();
    lua_getglobal(L, name);
    T value{};
    if constexpr (std::is_same_v<T, std::string>) {
      const char *s = lua_tostring(L, -1);
      value = s ? s : "<not a string>";
    } else if constexpr (std::is_same_v<T, bool>) {
      value = lua_toboolean(L, -1);
    } else {
      value = static_cast<T>(lua_tonumber(L, -1));
    }
    lua_pop(L, 1);
    return value;
  }

  /// Converts the Scene in global `name` into the plain model.
  Scene convertGlobal(const char *name) {
    lua_State *L = state_->state();
    lua_getglobal(L, name);
    const SceneObj *scene = toObject<SceneObj>(L, -1);
    lua_pop(L, 1); // the global keeps it alive
    if (!scene) throw std::runtime_error(std::string(name) + " is not a Scene");
    return convertScene(*scene, state_->context());
  }

  /// The SceneError text of converting global `name`, or "no error".
  std::string conversionError(const char *name) {
    try {
      convertGlobal(name);
    } catch (const SceneError &e) {
      return e.what();
    }
    return "no error";
  }

  lua_State *L() { return state_->state(); }

  std::unique_ptr<ScriptState> state_;
};

} // namespace lray::lua
