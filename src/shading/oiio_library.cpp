// Pipeline: shading. See oiio_library.h: liblray_oiio.so, from the build
// that made this program (LRAY_OIIO_MODULE) or beside the executable.
#include "shading/oiio_library.h"

#include "util/module_loader.h"

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>

namespace lray {

namespace {

std::atomic<const OiioLibrary *> loaded{nullptr};

const OiioLibrary *load() {
  std::string tried;
  void *entry = loadModuleEntry(LRAY_OIIO_MODULE, "liblray_oiio.so", "lray_oiio_library", tried);
  if (!entry)
    throw std::runtime_error("cannot load LRay's OpenImageIO module (needed for image textures "
                             "and EXR output):" + tried);
  return reinterpret_cast<const OiioLibrary *(*)()>(entry)();
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
