// Pipeline: application (live preview; a module of its own). The preview
// page's HTTP server on cpp-httplib, built as liblray_preview.so and loaded
// by preview_server.cpp only for --watch --serve: Debian's cpp-httplib brings
// a dozen libraries (OpenSSL, Brotli, zlib) that every start of lray would
// otherwise load.
#include "app/watch/preview_server.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace lray {

namespace fs = std::filesystem;

struct PreviewServer::Impl {
  PreviewState &state;
  std::string host;
  int port = 0;
  httplib::Server server;
  std::thread thread;

  explicit Impl(PreviewState &s) : state(s) {}

  bool loopback() const { return host == "127.0.0.1" || host == "localhost" || host == "::1"; }

  /// The request's Host is one this server answers to.
  bool hostAllowed(const httplib::Request &req) const {
    if (!loopback()) return true;
    const std::string h = req.get_header_value("Host");
    const std::string p = ":" + std::to_string(port);
    return h == "127.0.0.1" + p || h == "localhost" + p || h == "[::1]" + p;
  }

  /// No Origin (a same-origin GET, curl) or this page's own origin.
  bool sameOrigin(const httplib::Request &req) const {
    if (!req.has_header("Origin")) return true;
    return req.get_header_value("Origin") == "http://" + req.get_header_value("Host");
  }

  void refuse(httplib::Response &res, int status, const std::string &why) {
    res.status = status;
    res.set_content(why + "\n", "text/plain");
  }

  void routes() {
    server.set_pre_routing_handler([this](const httplib::Request &req, httplib::Response &res) {
      if (hostAllowed(req)) return httplib::Server::HandlerResponse::Unhandled;
      refuse(res, 403, "this preview answers only to its loopback address");
      return httplib::Server::HandlerResponse::Handled;
    });
    server.Get("/", [](const httplib::Request &, httplib::Response &res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(previewPage(), "text/html; charset=utf-8");
    });
    server.Get("/image.png", [this](const httplib::Request &, httplib::Response &res) {
      auto image = state.image();
      if (!image) return refuse(res, 404, "no image yet");
      res.set_header("Cache-Control", "no-store");
      res.set_content(reinterpret_cast<const char *>(image->data()), image->size(), "image/png");
    });
    server.Get("/status", [this](const httplib::Request &, httplib::Response &res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(state.statusJson(), "application/json");
    });
    server.Get("/events", [this](const httplib::Request &req, httplib::Response &res) {
      if (!sameOrigin(req)) return refuse(res, 403, "events are for this page's own origin");
      res.set_header("Cache-Control", "no-store");
      auto sent = std::make_shared<uint64_t>(~uint64_t{0});
      res.set_chunked_content_provider("text/event-stream", [this, sent](size_t, httplib::DataSink &sink) {
        if (state.stopped()) return false;
        // The current status at once, then each new one; a comment line
        // every 15 s keeps proxies from closing an idle stream.
        const uint64_t now = *sent == ~uint64_t{0} ? state.version()
                                                   : state.waitPast(*sent, std::chrono::seconds(15));
        if (state.stopped()) return false;
        std::string chunk = ": idle\n\n";
        if (now != *sent) {
          chunk = "data: " + state.statusJson() + "\n\n";
          *sent = now;
        }
        return sink.write(chunk.data(), chunk.size());
      });
    });
    server.Post("/control", [this](const httplib::Request &req, httplib::Response &res) {
      if (!sameOrigin(req)) return refuse(res, 403, "actions are for this page's own origin");
      nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
      if (!body.is_object()) return refuse(res, 400, "expected a JSON object");
      PreviewRequest r;
      if (body.contains("frame")) {
        if (!body["frame"].is_number_integer() || body["frame"].get<long>() < 0)
          return refuse(res, 400, "frame: expected a frame number");
        r.frame = static_cast<int>(std::min<long>(body["frame"].get<long>(), 1L << 30));
      }
      if (body.contains("backend")) {
        if (!body["backend"].is_string()) return refuse(res, 400, "backend: expected a name");
        r.backend = body["backend"].get<std::string>();
      }
      state.request(r);
      res.status = 204;
    });
    server.Post("/save", [this](const httplib::Request &req, httplib::Response &res) {
      if (!sameOrigin(req)) return refuse(res, 403, "actions are for this page's own origin");
      auto image = state.image();
      const std::string path = state.savePath();
      if (!image || path.empty()) return refuse(res, 409, "no image to save yet");
      // The path is the watch loop's, never the request's.
      const std::string tmp = path + ".tmp" + std::to_string(getpid());
      {
        std::ofstream out(tmp, std::ios::binary);
        out.write(reinterpret_cast<const char *>(image->data()), static_cast<std::streamsize>(image->size()));
        if (!out.flush()) {
          std::error_code ec;
          fs::remove(tmp, ec);
          return refuse(res, 500, "cannot write " + path);
        }
      }
      std::error_code ec;
      fs::rename(tmp, path, ec);
      if (ec) {
        fs::remove(tmp, ec);
        return refuse(res, 500, "cannot write " + path);
      }
      res.set_content(nlohmann::json{{"path", path}}.dump(), "application/json");
    });
  }
};

namespace {

void *startServer(PreviewState &state, const std::string &host, int port, int &bound,
                  std::string &error) {
  auto impl = std::make_unique<PreviewServer::Impl>(state);
  impl->host = host;
  impl->routes();
  if (port == 0) {
    impl->port = impl->server.bind_to_any_port(host.c_str());
  } else if (impl->server.bind_to_port(host.c_str(), port)) {
    impl->port = port;
  }
  if (impl->port <= 0) {
    error = "cannot listen there (in use, or not an address of this machine)";
    return nullptr;
  }
  bound = impl->port;
  PreviewServer::Impl *raw = impl.get();
  impl->thread = std::thread([raw] { raw->server.listen_after_bind(); });
  return impl.release();
}

void stopServer(void *handle) {
  auto *impl = static_cast<PreviewServer::Impl *>(handle);
  impl->state.stop();
  impl->server.stop();
  if (impl->thread.joinable()) impl->thread.join();
  delete impl;
}

} // namespace

} // namespace lray

extern "C" const lray::PreviewLibrary *lray_preview_library() {
  static const lray::PreviewLibrary library{&lray::startServer, &lray::stopServer};
  return &library;
}
