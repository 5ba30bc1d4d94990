// Pipeline: application (live preview). See preview_server.h: the server
// lives in liblray_preview.so (preview_module.cpp), loaded on first use
// from the build that made this program (LRAY_PREVIEW_MODULE) or from
// beside the executable.
#include "app/watch/preview_server.h"

#include "util/module_loader.h"
#include "util/scene_error.h"

#include <mutex>

namespace lray {

namespace {

const PreviewLibrary *load(std::string &tried) {
  void *entry = loadModuleEntry(LRAY_PREVIEW_MODULE, "liblray_preview.so", "lray_preview_library",
                                tried);
  return entry ? reinterpret_cast<const PreviewLibrary *(*)()>(entry)() : nullptr;
}

} // namespace

const PreviewLibrary &previewLibrary() {
  static std::once_flag once;
  static const PreviewLibrary *library = nullptr;
  static std::string tried;
  // Nothing may throw inside call_once (see shading/oiio_library.cpp).
  std::call_once(once, [] {
    try {
      library = load(tried);
    } catch (...) {
      library = nullptr;
    }
  });
  if (!library) throw SceneError("--serve: cannot load LRay's preview server module:" + tried);
  return *library;
}

PreviewServer::PreviewServer(PreviewState &state, const std::string &host, int port)
    : host_(host) {
  std::string error;
  handle_ = previewLibrary().start(state, host, port, port_, error);
  if (!handle_) throw SceneError("--serve " + host + ":" + std::to_string(port) + ": " + error);
}

PreviewServer::~PreviewServer() { stop(); }

std::string PreviewServer::url() const {
  const std::string h = host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_;
  return "http://" + h + ":" + std::to_string(port_) + "/";
}

void PreviewServer::stop() {
  if (!handle_) return;
  previewLibrary().stop(handle_);
  handle_ = nullptr;
}

} // namespace lray
