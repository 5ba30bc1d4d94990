// Pipeline: application (live preview). See http_framing.h.
#include "app/watch/http_framing.h"

#include <cstdint>

namespace lray {

namespace {

RequestFrame refused(int status, std::string_view reason) {
  RequestFrame f;
  f.state = RequestFrame::State::Refused;
  f.status = status;
  f.reason = reason;
  return f;
}

bool sameNameIgnoringCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const char x = a[i] >= 'A' && a[i] <= 'Z' ? char(a[i] - 'A' + 'a') : a[i];
    if (x != b[i]) return false;
  }
  return true;
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  return s;
}

/// Digits only, no sign, no overflow (at most 18 digits: < 10^18).
bool parseLength(std::string_view s, uint64_t &value) {
  if (s.empty() || s.size() > 18) return false;
  value = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + uint64_t(c - '0');
  }
  return true;
}

} // namespace

RequestFrame frameRequest(std::string_view buffered, const HttpLimits &limits) {
  // Clients may send an empty line or two between requests (RFC 9112 2.2).
  size_t start = 0;
  while (start + 1 < buffered.size() && buffered[start] == '\r' && buffered[start + 1] == '\n')
    start += 2;
  if (start >= limits.maxHead) return refused(400, "only empty lines");
  const std::string_view scan = buffered.substr(start, limits.maxHead);
  const size_t end = scan.find("\r\n\r\n");
  if (end == std::string_view::npos) {
    if (scan.size() >= limits.maxHead) return refused(431, "request head too large");
    // A line end other than CRLF can be refused before the head is whole.
    for (size_t i = 0; i < scan.size(); ++i)
      if ((scan[i] == '\n' && (i == 0 || scan[i - 1] != '\r')) ||
          (scan[i] == '\r' && i + 1 < scan.size() && scan[i + 1] != '\n'))
        return refused(400, "a line of the request does not end in CRLF");
    return {};
  }
  const std::string_view head = scan.substr(0, end + 2); // each line with its CRLF
  uint64_t length = 0;
  bool haveLength = false;
  size_t lines = 0;
  for (size_t pos = 0; pos < head.size();) {
    const size_t eol = head.find("\r\n", pos);
    const std::string_view line = head.substr(pos, eol - pos);
    pos = eol + 2;
    if (line.find_first_of("\r\n") != std::string_view::npos)
      return refused(400, "a line of the request does not end in CRLF");
    if (lines++ == 0) continue; // the request line: httplib's to read
    if (lines - 1 > limits.maxHeaders) return refused(431, "too many request headers");
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos) continue; // httplib skips such a line too
    const std::string_view name = line.substr(0, colon);
    const std::string_view value = trimmed(line.substr(colon + 1));
    if (sameNameIgnoringCase(name, "transfer-encoding"))
      return refused(501, "request bodies must have a Content-Length");
    if (sameNameIgnoringCase(name, "content-length")) {
      uint64_t v = 0;
      if (!parseLength(value, v) || (haveLength && v != length))
        return refused(400, "bad Content-Length");
      length = v;
      haveLength = true;
    }
  }
  if (length > limits.maxBody) return refused(413, "request body too large");
  const size_t total = end + 4 + size_t(length);
  if (buffered.size() - start < total) return {};
  RequestFrame f;
  f.state = RequestFrame::State::Complete;
  f.begin = start;
  f.length = total;
  return f;
}

} // namespace lray
