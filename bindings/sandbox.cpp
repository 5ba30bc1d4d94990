// Pipeline: script -> scene description. See sandbox.h.
#include "bindings/sandbox.h"

#include "bindings/lua_binding.h"

#include <cstdlib>
#include <cstring>
#include <string>

namespace lray::lua {

namespace {

// Each restricted function is a C closure whose first upvalue is the
// unrestricted one: its checks call nothing a script can replace (a Lua
// wrapper calling the global `error` or `type` could be talked out of its
// check by a script that redefined them).

/// Raises `message` as an error at the script line that called.
[[noreturn]] void refuse(lua_State *L, const char *message) {
  pushErrorMessage(L, message);
  lua_error(L);
  std::abort(); // lua_error does not return
}

/// Pushes the path at `index` resolved against the scene's folder
/// (BindingContext::resolveReadPath), or raises its refusal at the
/// caller's line. The path is checked before protectedCall (a Lua error
/// must not cross its C++ objects).
void pushReadable(lua_State *L, int index, const char *what) {
  const char *path = luaL_checkstring(L, index);
  protectedCall(L, [&] {
    const std::string resolved = BindingContext::of(L).resolveReadPath(path, what);
    lua_pushlstring(L, resolved.data(), resolved.size());
    return 1;
  });
}

/// Calls the closure's unrestricted function (upvalue 1) with the values
/// pushed above `base`, returning all its results.
int callRaw(lua_State *L, int base) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, base + 1);
  lua_call(L, lua_gettop(L) - base - 1, LUA_MULTRET);
  return lua_gettop(L) - base;
}

int open(lua_State *L) {
  const char *mode = luaL_optstring(L, 2, "r");
  if (std::strcmp(mode, "r") != 0 && std::strcmp(mode, "rb") != 0)
    refuse(L, "io.open: only read mode is allowed in scene scripts (--unsafe lifts this)");
  const int base = lua_gettop(L);
  pushReadable(L, 1, "io.open");
  lua_pushstring(L, mode);
  return callRaw(L, base);
}

int lines(lua_State *L) {
  if (lua_isnoneornil(L, 1)) refuse(L, "io.lines: a file name is required in scene scripts");
  const int args = lua_gettop(L), base = args;
  pushReadable(L, 1, "io.lines");
  for (int i = 2; i <= args; ++i) lua_pushvalue(L, i);
  return callRaw(L, base);
}

// Userdata (files, LRay objects) have C finalizers: a script that could
// reach their metatable could swap a Lua function in.
int getmetatable(lua_State *L) {
  if (lua_type(L, 1) == LUA_TUSERDATA) {
    lua_pushnil(L);
    return 1;
  }
  const int base = lua_gettop(L);
  lua_pushvalue(L, 1);
  return callRaw(L, base);
}

// Finalizers run with the debug hooks off, so the timeout could not stop
// one that loops, and one that resurrects an object the converter already
// took could hand it freed memory: scene scripts get none. Lua marks an
// object for finalization only when setmetatable sees __gc, so checking
// here is enough.
int setmetatable(lua_State *L) {
  if (lua_type(L, 2) == LUA_TTABLE) {
    lua_pushliteral(L, "__gc");
    const bool gc = lua_rawget(L, 2) != LUA_TNIL;
    lua_pop(L, 1);
    if (gc)
      refuse(L, "setmetatable: __gc finalizers are not allowed in scene scripts (--unsafe lifts "
                "this)");
  }
  const int args = lua_gettop(L), base = args;
  for (int i = 1; i <= args; ++i) lua_pushvalue(L, i);
  return callRaw(L, base);
}

// Binary chunks can break the interpreter's safety: text only.
int load(lua_State *L) {
  const int args = lua_gettop(L), base = args;
  lua_pushvalue(L, 1);
  lua_pushvalue(L, 2);
  lua_pushliteral(L, "t");
  if (args >= 4) lua_pushvalue(L, 4); // the environment
  return callRaw(L, base);
}

/// loadfile(path, mode, env): the file's text through the unrestricted
/// load (upvalue 1) as text only, read with the unrestricted io.open
/// (upvalue 2) from a path the scene may read.
int loadfile(lua_State *L) {
  const int env = lua_gettop(L) >= 3 ? 3 : 0;
  pushReadable(L, 1, "loadfile");
  lua_pushvalue(L, lua_upvalueindex(2));
  lua_pushvalue(L, -2);
  lua_pushliteral(L, "r");
  lua_call(L, 2, 2);
  if (lua_isnil(L, -2)) return 2; // nil and the reason
  lua_pop(L, 1);
  const int file = lua_gettop(L);
  lua_getfield(L, file, "read");
  lua_pushvalue(L, file);
  lua_pushliteral(L, "a");
  lua_call(L, 2, 1);
  const int text = lua_gettop(L);
  lua_getfield(L, file, "close");
  lua_pushvalue(L, file);
  lua_call(L, 1, 0);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushvalue(L, text);
  lua_pushfstring(L, "@%s", lua_tostring(L, 1));
  lua_pushliteral(L, "t");
  if (env) lua_pushvalue(L, env);
  lua_call(L, env ? 4 : 3, LUA_MULTRET);
  return lua_gettop(L) - text;
}

/// dofile(path): the restricted loadfile (upvalue 1), then the chunk.
int dofile(lua_State *L) {
  const int base = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushvalue(L, 1);
  lua_call(L, 1, 2);
  if (lua_isnil(L, -2)) refuse(L, lua_tostring(L, -1) ? lua_tostring(L, -1) : "dofile failed");
  lua_pop(L, 1);
  lua_call(L, 0, LUA_MULTRET);
  return lua_gettop(L) - base;
}

/// Replaces global `name` by `f` with the global's old value as upvalue.
void wrapGlobal(lua_State *L, const char *name, lua_CFunction f) {
  lua_getglobal(L, name);
  lua_pushcclosure(L, f, 1);
  lua_setglobal(L, name);
}

} // namespace

void openLibraries(lua_State *L, bool unsafe) {
  if (unsafe) {
    luaL_openlibs(L);
    return;
  }
  const luaL_Reg libs[] = {{LUA_GNAME, luaopen_base},     {LUA_MATHLIBNAME, luaopen_math},
                           {LUA_STRLIBNAME, luaopen_string}, {LUA_TABLIBNAME, luaopen_table},
                           {LUA_UTF8LIBNAME, luaopen_utf8}};
  for (const luaL_Reg &lib : libs) {
    luaL_requiref(L, lib.name, lib.func, 1);
    lua_pop(L, 1);
  }
  wrapGlobal(L, "getmetatable", &getmetatable);
  wrapGlobal(L, "setmetatable", &setmetatable);
  // io: read-only open and lines; the full library stays reachable only
  // from C (the registry) and as the closures' upvalues.
  luaL_requiref(L, LUA_IOLIBNAME, luaopen_io, 0);
  const int io = lua_gettop(L);
  lua_newtable(L);
  lua_getfield(L, io, "open");
  lua_pushcclosure(L, &open, 1);
  lua_setfield(L, -2, "open");
  lua_getfield(L, io, "lines");
  lua_pushcclosure(L, &lines, 1);
  lua_setfield(L, -2, "lines");
  lua_setglobal(L, "io");
  lua_getglobal(L, "load"); // the unrestricted load, for loadfile
  lua_getfield(L, io, "open");
  lua_pushcclosure(L, &loadfile, 2);
  lua_pushvalue(L, -1);
  lua_setglobal(L, "loadfile");
  lua_pushcclosure(L, &dofile, 1);
  lua_setglobal(L, "dofile");
  wrapGlobal(L, "load", &load);
  lua_settop(L, io - 1);
  // os: the clock and calendar only.
  luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
  lua_newtable(L);
  for (const char *name : {"clock", "time", "date"}) {
    lua_getfield(L, -2, name);
    lua_setfield(L, -2, name);
  }
  lua_setglobal(L, "os");
  lua_pop(L, 1);
}

} // namespace lray::lua
