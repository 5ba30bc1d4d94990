// Pipeline: shading. See oiio_library.h: dlopen of liblray_oiio.so, from the
// build that made this program (LRAY_OIIO_MODULE) or beside the executable.
#include "shading/oiio_library.h"

#include <dlfcn.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <system_error>

namespace lray {

namespace {

std::atomic<const OiioLibrary *> loaded{nullptr};

const OiioLibrary *load() {
  namespace fs = std::filesystem;
  std::string tried;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path &candidate :
       {fs::path(LRAY_OIIO_MODULE), ec ? fs::path() : exe.parent_path() / "liblray_oiio.so"}) {
    if (candidate.empty()) continue;
    // RTLD_LOCAL: the module's OpenImageIO symbols stay its own.
    void *handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char *why = dlerror();
      tried += "\n  " + candidate.string() + ": " + (why ? why : "cannot load");
      continue;
    }
    auto entry = reinterpret_cast<const OiioLibrary *(*)()>(dlsym(handle, "lray_oiio_library"));
    if (entry) return entry();
    tried += "\n  " + candidate.string() + ": no lray_oiio_library";
  }
  throw std::runtime_error("cannot load LRay's OpenImageIO module (needed for image textures "
                           "and EXR output):" + tried);
}

} // namespace

const OiioLibrary &oiioLibrary() {
  static std::once_flag once;
  std::call_once(once, [] { loaded = load(); });
  const OiioLibrary *library = loaded.load();
  if (!library) throw std::runtime_error("LRay's OpenImageIO module failed to load earlier");
  return *library;
}

bool oiioLibraryLoaded() { return loaded.load() != nullptr; }

} // namespace lray
