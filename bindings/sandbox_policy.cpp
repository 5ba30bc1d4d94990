// Pipeline: script -> scene description. See sandbox_policy.h.
#include "bindings/sandbox_policy.h"

#include "bindings/lua_binding.h"

#include <algorithm>

namespace lray::lua {

std::string SandboxPolicy::resolvePath(const std::string &file) const {
  namespace fs = std::filesystem;
  fs::path p(file);
  if (p.is_relative()) p = fs::path(baseDir) / p;
  return fs::absolute(p).lexically_normal().string();
}

std::string SandboxPolicy::readablePath(const std::string &file, const char *what) const {
  namespace fs = std::filesystem;
  const std::string path = resolvePath(file);
  std::error_code ec;
  if (!readRoots.empty()) {
    const fs::path real = fs::weakly_canonical(path, ec);
    bool inside = false;
    for (const fs::path &root : readRoots) {
      auto [r, p] = std::mismatch(root.begin(), root.end(), real.begin(), real.end());
      if (r == root.end()) {
        inside = true;
        break;
      }
    }
    if (ec || !inside) {
      std::string roots;
      for (const fs::path &root : readRoots) roots += (roots.empty() ? "" : ", ") + root.string();
      throw ScriptError(std::string(what) + ": '" + file + "' is outside the folders a scene may "
                        "read (" + roots + "; allow another with --allow-read DIR)");
    }
  }
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
    throw ScriptError(std::string(what) + ": '" + file + "' is not a regular file (" + path + ")");
  return path;
}

bool SandboxPolicy::pastMemoryLimit(lua_State *L) const {
  if (!allocator || !allocator->overLimit()) return false;
  lua_gc(L, LUA_GCCOLLECT);
  return allocator->overLimit();
}

void SandboxPolicy::checkMemory(lua_State *L, const char *what) const {
  if (pastMemoryLimit(L)) throw ScriptError(std::string(what) + ": " + allocator->limitMessage());
}

} // namespace lray::lua
