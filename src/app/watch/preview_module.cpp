// Pipeline: application (live preview; a module of its own). The preview
// page's HTTP server on cpp-httplib, built as liblray_preview.so and loaded
// by preview_server.cpp only for --watch --serve: Debian's cpp-httplib brings
// a dozen libraries (OpenSSL, Brotli, zlib) that every start of lray would
// otherwise load.
#include "app/watch/preview_server.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace lray {

namespace fs = std::filesystem;

/// The largest request body the page sends is a small JSON object.
constexpr size_t kMaxBody = 64 * 1024;

struct PreviewServer::Impl {
  PreviewState &state;
  std::string host;
  int port = 0;
  httplib::Server server;
  std::thread thread;

  explicit Impl(PreviewState &s) : state(s) {}

  /// Listening on a loopback address: any of 127.0.0.0/8 (127.0.0.2 and
  /// the short 127.1 included), ::1 or localhost.
  bool loopback() const {
    in_addr v4{};
    in6_addr v6{};
    if (host == "localhost" || (inet_pton(AF_INET6, host.c_str(), &v6) == 1 &&
                                IN6_IS_ADDR_LOOPBACK(&v6)))
      return true;
    return inet_aton(host.c_str(), &v4) != 0 && (ntohl(v4.s_addr) >> 24) == 127;
  }

  /// The request's Host is one this server answers to: on a loopback
  /// address only the loopback names and the address it was given (a
  /// foreign name is a DNS-rebinding page of another site).
  bool hostAllowed(const httplib::Request &req) const {
    if (!loopback()) return true;
    const std::string h = req.get_header_value("Host");
    const std::string given = host.find(':') != std::string::npos ? "[" + host + "]" : host;
    for (const std::string &name : {std::string("127.0.0.1"), std::string("localhost"),
                                    std::string("[::1]"), given})
      if (h == name + ":" + std::to_string(port) || (port == 80 && h == name)) return true;
    return false;
  }

  /// No Origin (a same-origin GET, curl) or this page's own origin.
  bool sameOrigin(const httplib::Request &req) const {
    if (!req.has_header("Origin")) return true;
    return req.get_header_value("Origin") == "http://" + req.get_header_value("Host");
  }

  /// One step of an event stream: the current status at once, then each
  /// new one; a comment line every 5 s shows whether the client is still
  /// there (its thread is freed at the first failed write) and keeps
  /// proxies from closing an idle stream.
  bool stream(uint64_t &sent, httplib::DataSink &sink) {
    if (state.stopped() || !sink.is_writable()) return false;
    const uint64_t now = sent == ~uint64_t{0} ? state.version()
                                              : state.waitPast(sent, std::chrono::seconds(5));
    if (state.stopped()) return false;
    std::string chunk = ": idle\n\n";
    if (now != sent) {
      chunk = "data: " + state.statusJson() + "\n\n";
      sent = now;
    }
    return sink.write(chunk.data(), chunk.size());
  }

  void refuse(httplib::Response &res, int status, const std::string &why) {
    res.status = status;
    res.set_content(why + "\n", "text/plain");
  }

  void routes() {
    // Each open page holds a thread for its event stream: room for many.
    server.new_task_queue = [] { return new httplib::ThreadPool(32); };
    // Bounds on what a client can make the server hold or wait for: the
    // page's requests are a few hundred bytes; a stalled or trickling
    // client is dropped after a few seconds.
    server.set_payload_max_length(kMaxBody);
    server.set_read_timeout(5, 0);
    server.set_write_timeout(5, 0);
    server.set_keep_alive_timeout(2);
    server.set_keep_alive_max_count(20);
    server.set_post_routing_handler([](const httplib::Request &, httplib::Response &res) {
      res.set_header("X-Frame-Options", "DENY"); // no page of another site may frame Save
    });
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
      res.set_chunked_content_provider(
          "text/event-stream", [this, sent](size_t, httplib::DataSink &sink) {
            try {
              return stream(*sent, sink);
            } catch (...) {
              return false; // nothing may escape a content provider: it would end the process
            }
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
      auto [image, path] = state.imageToSave();
      if (!image || path.empty()) return refuse(res, 409, "no image to save yet");
      // The path is the watch loop's, never the request's; two saves at
      // once write temporary files of their own.
      static std::atomic<unsigned> counter{0};
      const std::string tmp = (fs::path(path).parent_path() /
                               ("." + fs::path(path).filename().string() + ".tmp" +
                                std::to_string(getpid()) + "_" + std::to_string(counter++)))
                                  .string();
      {
        std::ofstream out(tmp, std::ios::binary);
        out.write(reinterpret_cast<const char *>(image->data()),
                  static_cast<std::streamsize>(image->size()));
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
  // stop() before the server runs would be lost and the join would hang:
  // return once it runs (bounded).
  for (int i = 0; i < 500 && !impl->server.is_running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
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
