// Pipeline: application (live preview). Where one HTTP request ends in the
// bytes a client has sent so far, with the preview server's size limits
// applied before anything is parsed or allocated for it. The request's
// meaning (routes, headers) is cpp-httplib's; this only frames it, so that
// a client can make the server hold at most one bounded request.
#pragma once

#include <cstddef>
#include <string_view>

namespace lray {

struct HttpLimits {
  size_t maxHead = 16 * 1024; ///< request line and headers, with their line ends
  size_t maxHeaders = 64;     ///< header lines
  size_t maxBody = 64 * 1024; ///< the page's largest request is a small JSON object
};

struct RequestFrame {
  enum class State { Incomplete, Complete, Refused };
  State state = State::Incomplete;
  size_t begin = 0;        ///< Complete: empty lines before the request
  size_t length = 0;       ///< Complete: bytes of the request, head and body
  int status = 0;          ///< Refused: the HTTP status to answer with
  std::string_view reason; ///< Refused: why, for the answer's body
};

/// Frames the request at the start of `buffered` (after empty lines,
/// which clients may send between requests): Complete: the request is
/// buffered.substr(begin, length) and begin + length bytes are used. Incomplete: wait for
/// more (a head that cannot end within the limits is Refused at once).
/// Refused: 400 (malformed: bare CR or LF, a bad or contradictory
/// Content-Length), 413 (body too large), 431 (head too large or too many
/// headers), 501 (Transfer-Encoding: bodies must have a length).
RequestFrame frameRequest(std::string_view buffered, const HttpLimits &limits);

} // namespace lray
