// Pipeline: script -> scene description. See sandbox.h.
#include "bindings/sandbox.h"

namespace lray::lua {

namespace {

// Runs with the unrestricted functions as arguments and replaces the
// globals by restricted wrappers; the originals stay only in upvalues.
const char kSandboxSetup[] = R"lua(
local rawload, rawopen, rawlines, base, clock, time, date = ...
local function resolve(path)
  if type(path) ~= "string" or path:sub(1, 1) == "/" then return path end
  return base .. "/" .. path
end
io = {
  open = function(path, mode)
    if mode ~= nil and mode ~= "r" and mode ~= "rb" then
      error("io.open: only read mode is allowed in scene scripts (--unsafe lifts this)", 2)
    end
    return rawopen(resolve(path), mode or "r")
  end,
  lines = function(path, ...)
    if path == nil then error("io.lines: a file name is required in scene scripts", 2) end
    return rawlines(resolve(path), ...)
  end,
}
os = { clock = clock, time = time, date = date }
load = function(chunk, name, mode, ...)
  -- Binary chunks can break the interpreter's safety: text only.
  return rawload(chunk, name, "t", ...)
end
loadfile = function(path, mode, ...)
  local f, err = rawopen(resolve(path), "r")
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

} // namespace

void openLibraries(lua_State *L, bool unsafe, const std::string &baseDir) {
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
  lua_pushlstring(L, baseDir.data(), baseDir.size());
  luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
  lua_getfield(L, -1, "clock");
  lua_getfield(L, -2, "time");
  lua_getfield(L, -3, "date");
  lua_remove(L, -4);
  // The full io and os tables stay reachable only from C (the registry).
  lua_call(L, 7, 0);
}

} // namespace lray::lua
