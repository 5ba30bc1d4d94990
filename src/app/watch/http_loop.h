// Pipeline: application (live preview; the server module). The preview
// server's sockets: one thread and one poll() loop for every connection,
// so no client, however slow or numerous, holds a worker that another
// request needs. Each connection holds at most one request (framed and
// bounded by http_framing) and one answer; every phase has a deadline
// (a whole request within 5 s of its first byte, an idle connection 5 s,
// an answer 10 s to drain); connections are capped (the oldest idle one
// makes room for a new one) and event streams are capped and pushed from
// this loop; stop() ends it at once whatever the clients do.
#pragma once

#include "app/watch/http_framing.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace lray {

/// What a request gets: the bytes to send, and whether the connection
/// closes after them or becomes an event stream (then the bytes are
/// dropped and the service's streamHead() and event()s are sent instead).
struct HttpAnswer {
  std::string bytes;
  bool close = false;
  bool stream = false;
};

/// What the loop serves (preview_routes.h). Called on the loop's thread.
class HttpService {
public:
  virtual ~HttpService() = default;
  /// One whole request; `last`: the connection closes after the answer.
  virtual HttpAnswer answer(std::string_view request, bool last, const std::string &peer,
                            int peerPort) = 0;
  /// An event stream's head, and its events: one at its start and one
  /// whenever version() changes.
  virtual std::string streamHead() = 0;
  virtual std::string event() = 0;
  virtual uint64_t version() = 0;
};

struct HttpLoopLimits {
  HttpLimits request;
  size_t maxConnections = 256;          ///< open at once (the process has 1024 descriptors)
  size_t maxStreams = 64;               ///< of them event streams; more get 503
  size_t maxQueued = size_t{256} << 20; ///< answer bytes waiting to be sent, all connections
  size_t maxStreamBacklog = 64 * 1024;  ///< a stream's unsent events before it is dropped
  int maxRequestsPerConnection = 100;
  std::chrono::milliseconds requestTime{5000}; ///< from a request's first byte to its last
  std::chrono::milliseconds idleTime{5000};    ///< a connection with no request under way
  std::chrono::milliseconds writeTime{10000};  ///< for an answer to drain
  std::chrono::milliseconds lingerTime{1000};  ///< reading what follows a refused request
  std::chrono::milliseconds pingTime{5000};    ///< a comment line on a quiet event stream
};

class HttpLoop {
public:
  /// Listens on host:port (port 0: any free one); null and why not.
  static std::unique_ptr<HttpLoop> listen(const std::string &host, int port, std::string &error,
                                          const HttpLoopLimits &limits = {});
  ~HttpLoop();
  HttpLoop(const HttpLoop &) = delete;
  HttpLoop &operator=(const HttpLoop &) = delete;

  int port() const { return port_; }
  /// Serves until stop() (call it from another thread).
  void run(HttpService &service);
  /// Makes run() return at once, closing every connection. Thread-safe.
  void stop();

private:
  struct Connection;
  HttpLoop(int listenFd, int wakeFd, int port, const HttpLoopLimits &limits);
  void acceptAll();
  bool evictOldestIdle();
  void readFrom(Connection &c);
  void writeTo(Connection &c);
  void answerBuffered(Connection &c, HttpService &service);
  void queue(Connection &c, std::string bytes, bool close);
  void pushEvents(HttpService &service);
  void close(Connection &c);

  int listenFd_, wakeFd_, port_;
  HttpLoopLimits limits_;
  std::atomic<bool> stopping_{false};
  std::vector<std::unique_ptr<Connection>> connections_;
  size_t queued_ = 0, streams_ = 0;
  std::chrono::steady_clock::time_point acceptPausedUntil_{};
};

} // namespace lray
