// Pipeline: script -> scene description. The libraries a scene script gets
// (lua/README.md, "The sandbox"): base, math, string, table, utf8, read-only io.open
// and io.lines, os.clock/time/date; text-only load. --unsafe opens all.
#pragma once

#include <lua.hpp>

#include <string>

namespace lray::lua {

/// Opens the libraries into L. Relative paths given to io.open, io.lines,
/// loadfile and dofile resolve against the script's folder, and reads are
/// confined to SandboxPolicy::readRoots (set before this is called).
void openLibraries(lua_State *L, bool unsafe);

} // namespace lray::lua
