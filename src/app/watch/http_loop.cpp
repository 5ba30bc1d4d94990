// Pipeline: application (live preview; the server module). See http_loop.h.
#include "app/watch/http_loop.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace lray {

using Clock = std::chrono::steady_clock;

struct HttpLoop::Connection {
  enum class Phase {
    Idle,      ///< no request under way
    Reading,   ///< part of a request is here
    Writing,   ///< an answer is being sent; nothing more is read meanwhile
    Streaming, ///< an event stream: events are sent, anything read is dropped
    Draining,  ///< refused and shut for writing: what the client still sends is read and dropped
  };
  int fd = -1;
  std::string peer;
  int peerPort = 0;
  std::string in, out;
  size_t sent = 0;
  Phase phase = Phase::Idle;
  Clock::time_point since, deadline; ///< the phase's start and its end at the latest
  bool closeAfter = false;
  bool unframed = false; ///< input came that frameRequest has not seen
  bool peerClosed = false; ///< the client shut its side after sending a request
  int answered = 0;
  size_t drained = 0;
  uint64_t version = 0; ///< Streaming: the version of the last event sent
  Clock::time_point nextPing;
};

namespace {

std::string peerName(const sockaddr_storage &ss, int &port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (ss.ss_family == AF_INET) {
    const auto &a = reinterpret_cast<const sockaddr_in &>(ss);
    inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
    port = ntohs(a.sin_port);
  } else if (ss.ss_family == AF_INET6) {
    const auto &a = reinterpret_cast<const sockaddr_in6 &>(ss);
    inet_ntop(AF_INET6, &a.sin6_addr, text, sizeof text);
    port = ntohs(a.sin6_port);
  }
  return text;
}

std::string refusal(int status, std::string_view reason) {
  const char *title = status == 400   ? "Bad Request"
                      : status == 413 ? "Content Too Large"
                      : status == 431 ? "Request Header Fields Too Large"
                      : status == 501 ? "Not Implemented"
                      : status == 503 ? "Service Unavailable"
                                      : "Error";
  const std::string body = std::string(reason) + "\n";
  return "HTTP/1.1 " + std::to_string(status) + " " + title +
         "\r\nContent-Type: text/plain\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nConnection: close\r\n\r\n" + body;
}

int millisecondsUntil(Clock::time_point t, Clock::time_point now) {
  if (t <= now) return 0;
  return int(std::chrono::ceil<std::chrono::milliseconds>(t - now).count());
}

} // namespace

std::unique_ptr<HttpLoop> HttpLoop::listen(const std::string &host, int port, std::string &error,
                                           const HttpLoopLimits &limits) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo *found = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found) {
    error = "not an address of this machine";
    return nullptr;
  }
  int fd = -1, why = 0;
  for (addrinfo *a = found; a && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    const int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, 128) != 0) {
      why = errno;
      ::close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(found);
  if (fd < 0) {
    error = "cannot listen there (" + std::string(why ? std::strerror(why) : "no address") + ")";
    return nullptr;
  }
  sockaddr_storage ss{};
  socklen_t len = sizeof ss;
  int bound = port;
  getsockname(fd, reinterpret_cast<sockaddr *>(&ss), &len);
  peerName(ss, bound);
  const int wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake < 0) {
    ::close(fd);
    error = std::strerror(errno);
    return nullptr;
  }
  return std::unique_ptr<HttpLoop>(new HttpLoop(fd, wake, bound, limits));
}

HttpLoop::HttpLoop(int listenFd, int wakeFd, int port, const HttpLoopLimits &limits)
    : listenFd_(listenFd), wakeFd_(wakeFd), port_(port), limits_(limits) {}

HttpLoop::~HttpLoop() {
  for (auto &c : connections_)
    if (c->fd >= 0) ::close(c->fd);
  ::close(listenFd_);
  ::close(wakeFd_);
}

void HttpLoop::stop() {
  stopping_ = true;
  const uint64_t one = 1;
  [[maybe_unused]] ssize_t n = ::write(wakeFd_, &one, sizeof one);
}

void HttpLoop::run(HttpService &service) {
  std::vector<pollfd> fds;
  while (!stopping_) {
    Clock::time_point now = Clock::now();
    fds.assign(
        {{wakeFd_, POLLIN, 0}, {listenFd_, short(now >= acceptPausedUntil_ ? POLLIN : 0), 0}});
    // Streams are checked for new events at least every 100 ms; every
    // deadline is kept to within a millisecond.
    int timeout = 100;
    for (auto &c : connections_) {
      short events = 0;
      if (c->out.size() > c->sent) events |= POLLOUT;
      if (c->phase != Connection::Phase::Writing && !c->peerClosed) events |= POLLIN;
      fds.push_back({c->fd, events, 0});
      if (c->phase != Connection::Phase::Streaming)
        timeout = std::min(timeout, millisecondsUntil(c->deadline, now));
      if (c->unframed && c->out.empty()) timeout = 0; // a pipelined request may be whole
    }
    if (::poll(fds.data(), fds.size(), timeout) < 0 && errno != EINTR) break;
    if (stopping_) break;
    if (fds[0].revents & POLLIN) {
      uint64_t n;
      [[maybe_unused]] ssize_t r = ::read(wakeFd_, &n, sizeof n);
    }
    const size_t polled = fds.size() - 2;
    for (size_t i = 0; i < polled; ++i) {
      Connection &c = *connections_[i];
      const short r = fds[i + 2].revents;
      try {
        // An error, or a client gone while its answer is sent: nothing
        // more can happen on it (and poll would report it again at once).
        if ((r & (POLLERR | POLLNVAL)) || ((r & POLLHUP) && c.phase == Connection::Phase::Writing))
          close(c);
        if (c.fd >= 0 && (r & (POLLIN | POLLHUP))) readFrom(c);
        if (c.fd >= 0 && (r & POLLOUT)) writeTo(c);
        if (c.fd >= 0) answerBuffered(c, service);
      } catch (...) {
        close(c); // out of memory answering one client: that client goes
      }
    }
    try {
      pushEvents(service);
    } catch (...) {
    }
    now = Clock::now();
    for (auto &c : connections_)
      if (c->fd >= 0 && c->phase != Connection::Phase::Streaming && now >= c->deadline) close(*c);
    connections_.erase(std::remove_if(connections_.begin(), connections_.end(),
                                      [](const auto &c) { return c->fd < 0; }),
                       connections_.end());
    if (fds[1].revents & POLLIN) acceptAll();
  }
  for (auto &c : connections_)
    close(*c);
  connections_.clear();
}

void HttpLoop::acceptAll() {
  for (int accepted = 0; accepted < 64; ++accepted) {
    sockaddr_storage ss{};
    socklen_t len = sizeof ss;
    const int fd =
        accept4(listenFd_, reinterpret_cast<sockaddr *>(&ss), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        // Out of descriptors: make room, or stop listening a moment
        // rather than spin on a listening socket that stays readable.
        if (!evictOldestIdle()) acceptPausedUntil_ = Clock::now() + std::chrono::milliseconds(100);
      }
      return;
    }
    size_t open = 0;
    for (auto &c : connections_)
      open += c->fd >= 0;
    if (open >= limits_.maxConnections && !evictOldestIdle()) {
      ::close(fd);
      continue;
    }
    auto c = std::make_unique<Connection>();
    c->fd = fd;
    c->peer = peerName(ss, c->peerPort);
    c->since = Clock::now();
    c->deadline = c->since + limits_.idleTime;
    connections_.push_back(std::move(c));
  }
}

/// Closes the connection that has waited longest without an answer or a
/// stream under way; false when every connection is busy.
bool HttpLoop::evictOldestIdle() {
  Connection *oldest = nullptr;
  for (auto &c : connections_)
    if (c->fd >= 0 && c->phase != Connection::Phase::Writing &&
        c->phase != Connection::Phase::Streaming && (!oldest || c->since < oldest->since))
      oldest = c.get();
  if (oldest) close(*oldest);
  return oldest != nullptr;
}

void HttpLoop::readFrom(Connection &c) {
  if (c.phase == Connection::Phase::Writing) return;
  char buf[16384];
  for (int round = 0; round < 4; ++round) {
    const ssize_t n = ::recv(c.fd, buf, sizeof buf, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (n == 0 && !c.in.empty() && c.phase == Connection::Phase::Reading) {
      c.peerClosed = true; // sent its request and shut its side: answer it, then close
      return;
    }
    if (n <= 0) return close(c); // the client went, or the connection broke
    switch (c.phase) {
    case Connection::Phase::Draining:
      c.drained += size_t(n);
      if (c.drained > (size_t{4} << 20)) return close(c);
      break;
    case Connection::Phase::Streaming:
      break;
    case Connection::Phase::Idle:
      c.phase = Connection::Phase::Reading;
      c.since = Clock::now();
      c.deadline = c.since + limits_.requestTime;
      [[fallthrough]];
    default:
      c.in.append(buf, size_t(n));
      c.unframed = true;
      // Framing refuses a request long before this; a client that keeps
      // sending past its refused request is not read further.
      if (c.in.size() > limits_.request.maxHead + limits_.request.maxBody + sizeof buf) return;
    }
  }
}

void HttpLoop::answerBuffered(Connection &c, HttpService &service) {
  if ((c.phase != Connection::Phase::Idle && c.phase != Connection::Phase::Reading) ||
      !c.out.empty() || !c.unframed)
    return;
  c.unframed = false;
  const RequestFrame f = frameRequest(c.in, limits_.request);
  if (f.state == RequestFrame::State::Incomplete) {
    if (c.peerClosed) close(c); // it will never be whole
    return;
  }
  if (f.state == RequestFrame::State::Refused) return queue(c, refusal(f.status, f.reason), true);
  const bool last = ++c.answered >= limits_.maxRequestsPerConnection || c.peerClosed;
  HttpAnswer a =
      service.answer(std::string_view(c.in).substr(f.begin, f.length), last, c.peer, c.peerPort);
  c.in.erase(0, f.begin + f.length);
  c.unframed = !c.in.empty();
  if (a.stream) {
    if (streams_ >= limits_.maxStreams)
      return queue(c, refusal(503, "too many event streams are open"), true);
    ++streams_;
    c.phase = Connection::Phase::Streaming;
    c.in.clear();
    c.unframed = false;
    c.nextPing = Clock::now() + limits_.pingTime;
    c.version = service.version();
    c.out = service.streamHead() + service.event();
    queued_ += c.out.size();
    return writeTo(c);
  }
  if (queued_ + a.bytes.size() > limits_.maxQueued)
    return queue(c, refusal(503, "the server is busy sending other answers"), true);
  queue(c, std::move(a.bytes), a.close);
}

void HttpLoop::queue(Connection &c, std::string bytes, bool close) {
  queued_ += bytes.size();
  c.out = std::move(bytes);
  c.sent = 0;
  c.closeAfter = close;
  c.phase = Connection::Phase::Writing;
  c.since = Clock::now();
  c.deadline = c.since + limits_.writeTime;
  writeTo(c);
}

void HttpLoop::writeTo(Connection &c) {
  while (c.sent < c.out.size()) {
    const ssize_t n =
        ::send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (n <= 0) return close(c);
    c.sent += size_t(n);
  }
  queued_ -= c.out.size();
  c.out.clear();
  c.sent = 0;
  if (c.phase == Connection::Phase::Streaming) return;
  c.since = Clock::now();
  if (c.closeAfter) {
    // Shut for writing, then read what the client still sends for a
    // moment: closing with unread data would reset the connection and
    // could lose the answer before the client reads it.
    ::shutdown(c.fd, SHUT_WR);
    c.phase = Connection::Phase::Draining;
    c.deadline = c.since + limits_.lingerTime;
    return;
  }
  c.phase = c.in.empty() ? Connection::Phase::Idle : Connection::Phase::Reading;
  c.deadline = c.since + (c.in.empty() ? limits_.idleTime : limits_.requestTime);
}

void HttpLoop::pushEvents(HttpService &service) {
  if (!streams_) return;
  const uint64_t version = service.version();
  const Clock::time_point now = Clock::now();
  std::string event;
  for (auto &c : connections_) {
    if (c->fd < 0 || c->phase != Connection::Phase::Streaming) continue;
    std::string chunk;
    if (c->version != version) {
      if (event.empty()) event = service.event();
      chunk = event;
      c->version = version;
    } else if (now >= c->nextPing) {
      chunk = ": idle\n\n"; // shows whether the client is still there
    } else {
      continue;
    }
    c->nextPing = now + limits_.pingTime;
    // A client that does not read its stream is dropped, not buffered for.
    if (c->out.size() - c->sent + chunk.size() > limits_.maxStreamBacklog) {
      close(*c);
      continue;
    }
    queued_ += chunk.size();
    c->out += chunk;
    writeTo(*c);
  }
}

void HttpLoop::close(Connection &c) {
  if (c.fd < 0) return;
  ::close(c.fd);
  c.fd = -1;
  queued_ -= c.out.size();
  c.out.clear();
  if (c.phase == Connection::Phase::Streaming) --streams_;
}

} // namespace lray
