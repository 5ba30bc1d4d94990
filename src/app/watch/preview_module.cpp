// Pipeline: application (live preview; a module of its own). The preview
// page's server, built as liblray_preview.so and loaded by
// preview_server.cpp only for --watch --serve: Debian's cpp-httplib brings
// a dozen libraries (OpenSSL, Brotli, zlib) that every start of lray would
// otherwise load. The routes are preview_routes' (cpp-httplib reads and
// answers each request); the sockets, limits and timeouts http_loop's.
#include "app/watch/http_loop.h"
#include "app/watch/preview_routes.h"
#include "app/watch/preview_server.h"

#include <thread>

namespace lray {

struct PreviewServer::Impl {
  PreviewState &state;
  std::unique_ptr<HttpLoop> loop;
  std::unique_ptr<PreviewRoutes> routes;
  std::thread thread;

  explicit Impl(PreviewState &s) : state(s) {}
};

namespace {

void *startServer(PreviewState &state, const std::string &host, int port, int &bound,
                  std::string &error) {
  try {
    auto impl = std::make_unique<PreviewServer::Impl>(state);
    impl->loop = HttpLoop::listen(host, port, error);
    if (!impl->loop) return nullptr;
    bound = impl->loop->port();
    impl->routes = std::make_unique<PreviewRoutes>(state, host, bound);
    PreviewServer::Impl *raw = impl.get();
    impl->thread = std::thread([raw] { raw->loop->run(*raw->routes); });
    return impl.release();
  } catch (const std::exception &e) {
    error = e.what(); // no thread, or no memory: nothing may escape the module
    return nullptr;
  }
}

void stopServer(void *handle) {
  auto *impl = static_cast<PreviewServer::Impl *>(handle);
  impl->state.stop();
  impl->loop->stop();
  if (impl->thread.joinable()) impl->thread.join();
  delete impl;
}

} // namespace

} // namespace lray

extern "C" const lray::PreviewLibrary *lray_preview_library() {
  static const lray::PreviewLibrary library{&lray::startServer, &lray::stopServer};
  return &library;
}
