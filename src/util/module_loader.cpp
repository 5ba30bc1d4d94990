// See module_loader.h.
#include "util/module_loader.h"

#include <dlfcn.h>

#include <filesystem>
#include <system_error>

namespace lray {

void *loadModuleEntry(const std::string &buildPath, const std::string &fileName,
                      const char *entry, std::string &tried) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path &candidate :
       {fs::path(buildPath), ec ? fs::path() : exe.parent_path() / fileName}) {
    if (candidate.empty()) continue;
    void *handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char *why = dlerror();
      tried += "\n  " + candidate.string() + ": " + (why ? why : "cannot load");
      continue;
    }
    if (void *function = dlsym(handle, entry)) return function;
    tried += "\n  " + candidate.string() + ": no " + entry;
  }
  return nullptr;
}

} // namespace lray
