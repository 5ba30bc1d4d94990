// Pipeline: script -> scene description. See sandbox.h.
#include "bindings/sandbox.h"

#include "bindings/lua_binding.h"

#include <string>

namespace lray::lua {

namespace {

// Runs with the unrestricted functions as arguments and replaces the
// globals by restricted wrappers; the originals stay only in upvalues.
const char kSandboxSetup[] = R"lua(
local rawload, rawopen, rawlines, readable, clock, time, date = ...
-- readable(path, what): the path resolved against the scene's folder, or
-- an error at the caller's line when it lies outside the folders a scene
-- may read, or is not a regular file.
io = {
  open = function(path, mode)
    if mode ~= nil and mode ~= "r" and mode ~= "rb" then
      error("io.open: only read mode is allowed in scene scripts (--unsafe lifts this)", 2)
    end
    return rawopen(readable(path, "io.open"), mode or "r")
  end,
  lines = function(path, ...)
    if path == nil then error("io.lines: a file name is required in scene scripts", 2) end
    return rawlines(readable(path, "io.lines"), ...)
  end,
}
os = { clock = clock, time = time, date = date }
-- Finalizers run with the debug hooks off, so the timeout could not stop
-- one that loops, and one that resurrects an object the converter already
-- took could hand it freed memory: scene scripts get none. Lua marks an
-- object for finalization only when setmetatable sees __gc, so checking
-- here is enough.
local rawsetmetatable, rawgetmetatable, rawget = setmetatable, getmetatable, rawget
-- Userdata (files, LRay objects) already have a C finalizer: a script that
-- could reach their metatable could swap a Lua function in.
getmetatable = function(v)
  if type(v) == "userdata" then return nil end
  return rawgetmetatable(v)
end
setmetatable = function(t, mt)
  if type(mt) == "table" and rawget(mt, "__gc") ~= nil then
    error("setmetatable: __gc finalizers are not allowed in scene scripts (--unsafe lifts this)", 2)
  end
  return rawsetmetatable(t, mt)
end
load = function(chunk, name, mode, ...)
  -- Binary chunks can break the interpreter's safety: text only.
  return rawload(chunk, name, "t", ...)
end
loadfile = function(path, mode, ...)
  local f, err = rawopen(readable(path, "loadfile"), "r")
  if not f then return nil, err end
  local text = f:read("a")
  f:close()
  return rawload(text, "@" .. path, "t", ...)
end
dofile = function(path)
  local f, err = loadfile(path)
  if not f then error(err, 2) end
  return f()
end
)lua";

/// The sandbox's readable(path, what): BindingContext::resolveReadPath,
/// its refusal raised as an error at the script line that asked. The
/// arguments are checked before protectedCall (their errors are Lua errors,
/// which must not cross its C++ objects).
int readable(lua_State *L) {
  const char *path = luaL_checkstring(L, 1);
  const char *what = luaL_checkstring(L, 2);
  return protectedCall(L, [&] {
    const std::string resolved = BindingContext::of(L).resolveReadPath(path, what);
    lua_pushlstring(L, resolved.data(), resolved.size());
    return 1;
  });
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
  if (luaL_loadbufferx(L, kSandboxSetup, sizeof kSandboxSetup - 1, "=sandbox", "t") != LUA_OK)
    lua_error(L); // a bug in the text above; only at startup
  lua_getglobal(L, "load");
  luaL_requiref(L, LUA_IOLIBNAME, luaopen_io, 0);
  lua_getfield(L, -1, "open");
  lua_getfield(L, -2, "lines");
  lua_remove(L, -3);
  lua_pushcfunction(L, &readable);
  luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
  lua_getfield(L, -1, "clock");
  lua_getfield(L, -2, "time");
  lua_getfield(L, -3, "date");
  lua_remove(L, -4);
  // The full io and os tables stay reachable only from C (the registry).
  lua_call(L, 7, 0);
}

} // namespace lray::lua
