// Pipeline: application (live preview). The page's HTTP server, as lray
// sees it: a module (liblray_preview.so) that serves the page, the current
// image, its status and event stream and two actions from a thread of its
// own. The routes are in preview_routes.h, the sockets, limits and
// timeouts in http_loop.h.
#pragma once

#include "app/watch/preview_state.h"

#include <memory>
#include <string>

namespace lray {

/// The module's entry points (preview_module.cpp). start: listens on
/// host:port (0: any free one) in a thread of its own and gives the port,
/// or null and why not; stop: stops and frees it.
struct PreviewLibrary {
  void *(*start)(PreviewState &state, const std::string &host, int port, int &bound,
                 std::string &error);
  void (*stop)(void *server);
};

/// The module, loaded once; throws SceneError when it cannot be.
const PreviewLibrary &previewLibrary();

class PreviewServer {
public:
  /// Listens on host:port in a thread of its own (port 0: any free port).
  /// Throws SceneError naming the address when it cannot bind.
  PreviewServer(PreviewState &state, const std::string &host, int port);
  ~PreviewServer();
  PreviewServer(const PreviewServer &) = delete;
  PreviewServer &operator=(const PreviewServer &) = delete;

  int port() const { return port_; }
  /// The page's address, e.g. http://127.0.0.1:8765/
  std::string url() const;
  void stop();

  struct Impl; ///< the module's

private:
  std::string host_;
  int port_ = 0;
  void *handle_ = nullptr;
};

/// The page (preview_page.cpp): one HTML document, no external assets.
const std::string &previewPage();

} // namespace lray
