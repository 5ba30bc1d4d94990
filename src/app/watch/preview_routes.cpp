// Pipeline: application (live preview; the server module). See
// preview_routes.h.
#include "app/watch/preview_routes.h"

#include "app/watch/preview_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace lray {

namespace fs = std::filesystem;

namespace {

/// httplib's view of one request: read from memory, answered into memory.
class MemoryStream : public httplib::Stream {
public:
  MemoryStream(std::string_view in, std::string &out, const std::string &peer, int peerPort)
      : in_(in), out_(out), peer_(peer), peerPort_(peerPort) {}
  bool is_readable() const override { return pos_ < in_.size(); }
  bool is_writable() const override { return true; }
  ssize_t read(char *ptr, size_t size) override {
    size = std::min(size, in_.size() - pos_);
    std::memcpy(ptr, in_.data() + pos_, size);
    pos_ += size;
    return static_cast<ssize_t>(size);
  }
  ssize_t write(const char *ptr, size_t size) override {
    out_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string &ip, int &port) const override {
    ip = peer_;
    port = peerPort_;
  }
  void get_local_ip_and_port(std::string &ip, int &port) const override {
    ip.clear();
    port = 0;
  }
  // httplib compares it with FD_SETSIZE; no socket is read through it.
  socket_t socket() const override { return 0; }

private:
  std::string_view in_;
  size_t pos_ = 0;
  std::string &out_;
  const std::string &peer_;
  int peerPort_;
};

void refuse(httplib::Response &res, int status, const std::string &why) {
  res.status = status;
  res.set_content(why + "\n", "text/plain");
}

} // namespace

PreviewRoutes::PreviewRoutes(PreviewState &state, std::string host, int port)
    : state_(state), host_(std::move(host)), port_(port) {
  routes();
}

HttpAnswer PreviewRoutes::answer(std::string_view request, bool last, const std::string &peer,
                                 int peerPort) {
  HttpAnswer a;
  MemoryStream stream(request, a.bytes, peer, peerPort);
  streamAsked_ = false;
  bool closed = false;
  const bool ok = process_request(stream, last, closed, nullptr);
  a.close = last || closed || !ok;
  a.stream = streamAsked_;
  if (a.bytes.empty()) { // nothing httplib could read: a malformed request line
    a.bytes = "HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
    a.close = true;
  }
  return a;
}

std::string PreviewRoutes::streamHead() {
  return "HTTP/1.1 200 OK\r\n"
         "Content-Type: text/event-stream\r\n"
         "Cache-Control: no-store\r\n"
         "X-Frame-Options: DENY\r\n"
         "Connection: close\r\n\r\n";
}

std::string PreviewRoutes::event() { return "data: " + state_.statusJson() + "\n\n"; }

uint64_t PreviewRoutes::version() { return state_.version(); }

/// Listening on a loopback address: any of 127.0.0.0/8 (127.0.0.2 and the
/// short 127.1 included), ::1 or localhost.
bool PreviewRoutes::loopback() const {
  in_addr v4{};
  in6_addr v6{};
  if (host_ == "localhost" ||
      (inet_pton(AF_INET6, host_.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6)))
    return true;
  return inet_aton(host_.c_str(), &v4) != 0 && (ntohl(v4.s_addr) >> 24) == 127;
}

/// The request's Host is one this server answers to: on a loopback address
/// only the loopback names and the address it was given (a foreign name is
/// a DNS-rebinding page of another site).
bool PreviewRoutes::hostAllowed(const httplib::Request &req) const {
  if (!loopback()) return true;
  const std::string h = req.get_header_value("Host");
  const std::string given = host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_;
  for (const std::string &name :
       {std::string("127.0.0.1"), std::string("localhost"), std::string("[::1]"), given})
    if (h == name + ":" + std::to_string(port_) || (port_ == 80 && h == name)) return true;
  return false;
}

/// No Origin (a same-origin GET, curl) or this page's own origin.
bool PreviewRoutes::sameOrigin(const httplib::Request &req) const {
  if (!req.has_header("Origin")) return true;
  return req.get_header_value("Origin") == "http://" + req.get_header_value("Host");
}

void PreviewRoutes::routes() {
  set_keep_alive_max_count(100);
  set_keep_alive_timeout(5); // http_loop's idle timeout, announced to clients
  set_post_routing_handler([](const httplib::Request &, httplib::Response &res) {
    res.set_header("X-Frame-Options", "DENY"); // no page of another site may frame Save
  });
  set_pre_routing_handler([this](const httplib::Request &req, httplib::Response &res) {
    if (hostAllowed(req)) return httplib::Server::HandlerResponse::Unhandled;
    refuse(res, 403, "this preview answers only to its loopback address");
    return httplib::Server::HandlerResponse::Handled;
  });
  Get("/", [](const httplib::Request &, httplib::Response &res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(previewPage(), "text/html; charset=utf-8");
  });
  Get("/image.png", [this](const httplib::Request &, httplib::Response &res) {
    auto image = state_.image();
    if (!image) return refuse(res, 404, "no image yet");
    res.set_header("Cache-Control", "no-store");
    res.set_content(reinterpret_cast<const char *>(image->data()), image->size(), "image/png");
  });
  Get("/status", [this](const httplib::Request &, httplib::Response &res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(state_.statusJson(), "application/json");
  });
  Get("/events", [this](const httplib::Request &req, httplib::Response &res) {
    if (!sameOrigin(req)) return refuse(res, 403, "events are for this page's own origin");
    if (req.method != "GET") return refuse(res, 405, "events are read with GET");
    streamAsked_ = true; // http_loop sends streamHead() and the events
  });
  Post("/control", [this](const httplib::Request &req, httplib::Response &res) {
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
    state_.request(r);
    res.status = 204;
  });
  Post("/save", [this](const httplib::Request &req, httplib::Response &res) {
    if (!sameOrigin(req)) return refuse(res, 403, "actions are for this page's own origin");
    save(res);
  });
}

void PreviewRoutes::save(httplib::Response &res) {
  auto [image, path] = state_.imageToSave();
  if (!image || path.empty()) return refuse(res, 409, "no image to save yet");
  // The path is the watch loop's, never the request's; two saves at once
  // write temporary files of their own.
  static std::atomic<unsigned> counter{0};
  const std::string tmp =
      (fs::path(path).parent_path() / ("." + fs::path(path).filename().string() + ".tmp" +
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
}

} // namespace lray
