// Fuzz target (libFuzzer): the preview server's request handling. The input
// bytes arrive as a client would send them, in pieces (each piece's length
// from one input byte), and are handled as app/watch/http_loop handles a
// connection: frameRequest finds each whole request within the limits, and
// PreviewRoutes (cpp-httplib reading from memory) answers it, pipelined
// requests one after another. A crash, a sanitizer report, an exception, a
// frame outside the bytes, a refusal with another status or an answer that
// is not an HTTP/1.1 response is a bug.
#include "app/watch/http_framing.h"
#include "app/watch/preview_routes.h"

#include <cstdint>
#include <cstdlib>
#include <string>

namespace {

lray::PreviewState &state() {
  static lray::PreviewState *s = [] {
    auto *st = new lray::PreviewState;
    lray::PreviewStatus status;
    status.state = "done";
    st->publish({0x89, 'P', 'N', 'G'}, status, ""); // no save path: Save answers 409
    return st;
  }();
  return *s;
}

void check(bool ok) {
  if (!ok) std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static lray::PreviewRoutes routes(state(), "127.0.0.1", 8765);
  lray::HttpLimits limits; // smaller than the server's, so that fuzzing reaches them
  limits.maxHead = 2048;
  limits.maxHeaders = 16;
  limits.maxBody = 512;
  std::string in;
  size_t pos = 0;
  while (pos < size) {
    const size_t piece = std::min<size_t>(1 + data[pos] % 128, size - pos - 1);
    in.append(reinterpret_cast<const char *>(data) + pos + 1, piece);
    pos += 1 + piece;
    for (;;) {
      const lray::RequestFrame f = lray::frameRequest(in, limits);
      if (f.state == lray::RequestFrame::State::Incomplete) {
        check(in.size() < limits.maxHead + limits.maxBody + 2 * limits.maxHead);
        break;
      }
      if (f.state == lray::RequestFrame::State::Refused) {
        check(f.status == 400 || f.status == 413 || f.status == 431 || f.status == 501);
        return 0; // http_loop answers and closes
      }
      check(f.length > 0 && f.begin + f.length <= in.size());
      check(f.length <= limits.maxHead + limits.maxBody + 4);
      const lray::HttpAnswer a =
          routes.answer(std::string_view(in).substr(f.begin, f.length), false, "127.0.0.1", 40000);
      check(a.bytes.rfind("HTTP/1.1 ", 0) == 0);
      state().takeRequest(); // a /control request: the watch loop's to take
      in.erase(0, f.begin + f.length);
      if (a.close || a.stream) return 0;
    }
  }
  return 0;
}
