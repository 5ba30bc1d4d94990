// See printable_text.h.
#include "util/printable_text.h"

#include <fmt/format.h>

#include <cmath>

namespace lray {

namespace {

/// The length of the valid UTF-8 sequence at `s[i]`, or 0.
size_t utf8Length(std::string_view s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
  // Overlong forms, surrogates and code points past U+10FFFF are invalid.
  const unsigned c1 = n > 1 ? byte(i + 1) : 0;
  if ((n == 2 && c < 0xc2) || (n == 3 && c == 0xe0 && c1 < 0xa0) ||
      (n == 3 && c == 0xed && c1 >= 0xa0) || (n == 4 && c == 0xf0 && c1 < 0x90) ||
      (n == 4 && (c > 0xf4 || (c == 0xf4 && c1 >= 0x90))))
    return 0;
  return n;
}

} // namespace

std::string printableText(std::string_view text, size_t maxBytes) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    if (out.size() >= maxBytes) {
      out += fmt::format(" ... ({} more bytes left out)", text.size() - i);
      break;
    }
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const size_t n = utf8Length(text, i);
    if (n == 0) {
      out += fmt::format("\\x{:02x}", c);
      ++i;
    } else if (n == 1 && ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7f)) {
      out += fmt::format("\\x{:02x}", c);
      ++i;
    } else if (n == 2 && c == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(text[i + 1])); // C1 control
      i += 2;
    } else {
      out.append(text.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string readableNumber(double value) { return fmt::format("{:.6g}", value); }

std::string readableCount(long double value) {
  if (value >= 0 && value < 1e15L) return fmt::format("{}", static_cast<unsigned long long>(value));
  return readableNumber(static_cast<double>(value));
}

} // namespace lray
