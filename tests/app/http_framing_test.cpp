// The preview server's request framing (app/watch/http_framing): where a
// request ends, and which are refused before anything is read for them.
#include "app/watch/http_framing.h"

#include <gtest/gtest.h>

#include <string>

namespace lray {
namespace {

using State = RequestFrame::State;

TEST(HttpFraming, AWholeRequestEndsAfterItsHeadAndBody) {
  const std::string get = "GET /status HTTP/1.1\r\nHost: a\r\n\r\n";
  RequestFrame f = frameRequest(get + "GET /", {});
  EXPECT_EQ(f.state, State::Complete);
  EXPECT_EQ(f.begin, 0u);
  EXPECT_EQ(f.length, get.size());
  const std::string post = "POST /control HTTP/1.1\r\ncontent-LENGTH:  5 \r\n\r\n";
  EXPECT_EQ(frameRequest(post + "{\"a\"", {}).state, State::Incomplete);
  f = frameRequest(post + "{\"a\"}extra", {});
  EXPECT_EQ(f.state, State::Complete);
  EXPECT_EQ(f.length, post.size() + 5);
  // Empty lines before a request are skipped (RFC 9112 2.2).
  f = frameRequest("\r\n\r\n" + get, {});
  EXPECT_EQ(f.state, State::Complete);
  EXPECT_EQ(f.begin, 4u);
  EXPECT_EQ(f.length, get.size());
  EXPECT_EQ(frameRequest("GET / HTTP/1.1\r\nHost: a\r\n", {}).state, State::Incomplete);
  EXPECT_EQ(frameRequest("", {}).state, State::Incomplete);
}

TEST(HttpFraming, OversizedHeadsAndBodiesAreRefusedBeforeTheyArrive) {
  HttpLimits limits;
  limits.maxHead = 1024;
  limits.maxHeaders = 8;
  limits.maxBody = 100;
  // A head that has not ended within the limit: refused without its end.
  RequestFrame f = frameRequest("GET / HTTP/1.1\r\nX: " + std::string(2000, 'a'), limits);
  EXPECT_EQ(f.state, State::Refused);
  EXPECT_EQ(f.status, 431);
  std::string many = "GET / HTTP/1.1\r\n";
  for (int i = 0; i < 9; ++i)
    many += "X-" + std::to_string(i) + ": y\r\n";
  EXPECT_EQ(frameRequest(many + "\r\n", limits).status, 431);
  // A body longer than the limit: refused on its Content-Length alone.
  f = frameRequest("POST / HTTP/1.1\r\nContent-Length: 101\r\n\r\n", limits);
  EXPECT_EQ(f.state, State::Refused);
  EXPECT_EQ(f.status, 413);
  EXPECT_EQ(frameRequest("POST / HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n", limits)
                .status,
            400);
  EXPECT_EQ(frameRequest("GET / HTTP/1.1\r\rX", limits).status, 400);
  EXPECT_EQ(frameRequest(std::string(2000, ' '), limits).status, 431);
  std::string crlfs;
  for (int i = 0; i < 600; ++i)
    crlfs += "\r\n";
  EXPECT_EQ(frameRequest(crlfs, limits).status, 400);
}

TEST(HttpFraming, AmbiguousFramingIsRefused) {
  for (const char *head : {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n"}) {
    const RequestFrame f = frameRequest(head, {});
    EXPECT_EQ(f.state, State::Refused) << head;
    EXPECT_EQ(f.status, 501) << head;
  }
  for (const char *head :
       {"POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: +1\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: 1 2\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length:\r\n\r\n", "GET / HTTP/1.1\nHost: a\r\n\r\n",
        "GET / HTTP/1.1\r\nA: b\rc\r\n\r\n"}) {
    const RequestFrame f = frameRequest(head, {});
    EXPECT_EQ(f.state, State::Refused) << head;
    EXPECT_EQ(f.status, 400) << head;
  }
  // The same length twice is one length.
  EXPECT_EQ(
      frameRequest("POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 1\r\n\r\nx", {}).state,
      State::Complete);
}

} // namespace
} // namespace lray
