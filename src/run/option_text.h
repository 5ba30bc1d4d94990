// Pipeline: run. Conversions of option text shared by the option groups
// (option_group.h), with the messages lray's usage errors use.
#pragma once

#include <CLI/CLI.hpp>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace lray::option_text {

/// A finite number >= 0 (or > 0): CLI11's PositiveNumber reports its range
/// with 309 digits of DBL_MAX.
inline CLI::Validator finiteNumber(bool zeroAllowed) {
  return CLI::Validator(
      [zeroAllowed](std::string &input) -> std::string {
        size_t used = 0;
        double v = -1;
        try {
          v = std::stod(input, &used);
        } catch (const std::exception &) {
          used = 0;
        }
        if (used != input.size() || !std::isfinite(v) || v < 0 || (v == 0 && !zeroAllowed))
          return std::string(zeroAllowed ? "expects a number >= 0" : "expects a positive number") +
                 ", got '" + input + "'";
        return {};
      },
      zeroAllowed ? "NUMBER" : "POSITIVE");
}

/// `text`, in any case, looked up in `table`; an unknown name gives the
/// message naming the known ones (`known`), returned ("" on success).
template <class T>
std::string lookUp(std::string text, const std::map<std::string, T> &table, const char *option,
                   const std::string &known, T &out) {
  for (char &c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  auto it = table.find(text);
  if (it == table.end())
    return std::string(option) + ": unknown value '" + text + "' (expected " + known +
           "; run 'lray --help' for usage)";
  out = it->second;
  return {};
}

/// A positive whole number of bytes, or of KiB, MiB or GiB ("512M", "4G").
inline std::string parseSize(const std::string &text, const char *option, uint64_t &out) {
  size_t used = 0;
  unsigned long long n = 0;
  try {
    if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0])))
      n = std::stoull(text, &used);
  } catch (const std::exception &) {
    used = 0;
  }
  const std::string unit = used ? text.substr(used) : "";
  const std::map<std::string, int> shifts{{"", 0},  {"K", 10}, {"M", 20}, {"G", 30},
                                          {"k", 10}, {"m", 20}, {"g", 30}};
  auto shift = shifts.find(unit);
  if (!used || n == 0 || shift == shifts.end() || n > (~0ull >> (shift->second + 1)))
    return std::string(option) + ": expects a size such as 512M or 4G, got '" + text + "'";
  out = static_cast<uint64_t>(n) << shift->second;
  return {};
}

/// Non-negative integers of at most 9 digits separated by `separator`,
/// e.g. "3:9:2" or "1/4".
inline bool numbers(const std::string &text, char separator, std::vector<int> &out) {
  out.clear();
  size_t start = 0;
  for (;;) {
    size_t end = text.find(separator, start);
    std::string part =
        text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (part.empty() || part.size() > 9 ||
        part.find_first_not_of("0123456789") != std::string::npos)
      return false;
    out.push_back(std::stoi(part));
    if (end == std::string::npos) return true;
    start = end + 1;
  }
}

/// "--frames '3:x': why".
inline std::string valueError(const char *option, const std::string &value,
                              const std::string &why) {
  return std::string(option) + " '" + value + "': " + why;
}

} // namespace lray::option_text
