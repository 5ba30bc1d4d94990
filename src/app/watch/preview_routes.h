// Pipeline: application (live preview; the server module). The page's
// routes on cpp-httplib: the page itself, the current image, its status,
// the event stream and two actions (render another frame or with another
// backend; save the image). No request path ever reaches the file system:
// there are only these routes, everything else is 404. Requests from other
// origins are refused for the event stream and the actions, and a server
// bound to loopback answers only to loopback host names (no DNS rebinding).
// httplib reads each request from memory and writes its answer to memory:
// the sockets, limits and timeouts are http_loop's.
#pragma once

#include "app/watch/http_loop.h"
#include "app/watch/preview_state.h"

#include <httplib.h>

#include <string>
#include <string_view>

namespace lray {

class PreviewRoutes : public HttpService, private httplib::Server {
public:
  /// `host` and `port`: where the server listens (its Host check).
  PreviewRoutes(PreviewState &state, std::string host, int port);

  /// Answers one whole request (framed by frameRequest). `last`: the
  /// connection closes after this answer whatever the client asked.
  HttpAnswer answer(std::string_view request, bool last, const std::string &peer,
                    int peerPort) override;
  /// An event stream's head (no length: it ends when the connection does)
  /// and its events: the status as JSON, at each new version of it.
  std::string streamHead() override;
  std::string event() override;
  uint64_t version() override;

private:
  bool loopback() const;
  bool hostAllowed(const httplib::Request &req) const;
  bool sameOrigin(const httplib::Request &req) const;
  void routes();
  void save(httplib::Response &res);

  PreviewState &state_;
  std::string host_;
  int port_;
  bool streamAsked_ = false; ///< set by /events during answer()
};

} // namespace lray
