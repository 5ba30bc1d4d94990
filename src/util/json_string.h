// A string as a JSON string literal, for the hand-written JSON of --stats
// and --info (flat objects of numbers and a few strings need no library).
#pragma once

#include <fmt/format.h>

#include <string>

namespace lray {

inline std::string jsonString(const std::string &s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\t': out += "\\t"; break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", c);
      else out += c;
    }
  }
  return out + "\"";
}

} // namespace lray
