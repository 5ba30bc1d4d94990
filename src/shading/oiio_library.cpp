// Pipeline: shading. See oiio_library.h: liblray_oiio.so, from the build
// that made this program (LRAY_OIIO_MODULE) or beside the executable.
#include "shading/oiio_library.h"

#include "util/module_loader.h"

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

namespace lray {

namespace {

std::atomic<const OiioLibrary *> loaded{nullptr};
std::string failure; ///< why load() failed; written once, inside call_once

const OiioLibrary *load() {
  // OpenImageIO pulls in OpenCV and with it OpenBLAS, whose constructor
  // starts a worker per core that retries its 128 MiB buffer forever when
  // an address-space limit (ulimit -v) refuses it, and the process then
  // hangs at exit joining them. LRay never calls BLAS: one thread, none
  // started.
  setenv("OPENBLAS_NUM_THREADS", "1", 1);
  std::string tried;
  if (std::string why = probeModuleUnderLimit(LRAY_OIIO_MODULE, "liblray_oiio.so",
                                              "lray_oiio_library", 30);
      !why.empty()) {
    failure = "not enough memory to load LRay's OpenImageIO module (needed for image textures "
              "and EXR output) under this process's address-space limit (ulimit -v): " + why;
    return nullptr;
  }
  void *entry = loadModuleEntry(LRAY_OIIO_MODULE, "liblray_oiio.so", "lray_oiio_library", tried);
  if (entry) return reinterpret_cast<const OiioLibrary *(*)()>(entry)();
  const std::string what = "LRay's OpenImageIO module (needed for image textures and EXR output)";
  // Its ~260 libraries need a few hundred MiB of address space: under a
  // tight limit (ulimit -v) that is what fails, and the user should hear so.
  if (moduleFailedForMemory(tried))
    failure = "not enough memory to load " + what + ":" + tried;
  else
    failure = "cannot load " + what + ":" + tried;
  return nullptr;
}

} // namespace

const OiioLibrary &oiioLibrary() {
  // Nothing throws inside call_once: libstdc++'s call_once over glibc
  // aborts ("The futex facility returned an unexpected error code") when
  // its function throws, as load() could under a memory limit.
  static std::once_flag once;
  std::call_once(once, [] {
    try {
      loaded = load();
    } catch (...) { // out of memory while loading: failure stays as it was
    }
  });
  const OiioLibrary *library = loaded.load();
  if (!library)
    throw SceneError(failure.empty()
                         ? "not enough memory to load LRay's OpenImageIO module (needed for "
                           "image textures and EXR output)"
                         : failure);
  return *library;
}

bool oiioLibraryLoaded() { return loaded.load() != nullptr; }

} // namespace lray
