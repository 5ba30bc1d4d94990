// Pipeline: scene description. OBJ text -> MeshSource (see obj_loader.h).
#include "scene/obj_loader.h"

#include "scene/scene_checks.h"

#include "util/memory_budget.h"
#include "util/scene_error.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace lray {

namespace {

class ObjParser {
public:
  ObjParser(const std::string &displayName, uint64_t memoryBytes)
      : name_(displayName), memoryBytes_(memoryBytes) {}

  void parse(std::string_view text) {
    size_t pos = 0;
    while (pos < text.size()) {
      size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) end = text.size();
      ++line_;
      parseLine(text.substr(pos, end - pos));
      // Checked as the arrays grow, not once they are complete: a 64 MiB
      // limit must not see 574 MiB first.
      if (memoryBytes_ && text.size() + heldBytes() > memoryBytes_)
        fail("the OBJ file needs more than the " + bytesText(memoryBytes_) +
             " the script has left of its memory (raise it with --script-memory)");
      pos = end + 1;
    }
  }

  MeshSource take() { return std::move(mesh_); }

private:
  uint64_t heldBytes() const {
    return mesh_.positions.capacity() * sizeof(Vec3f) + mesh_.normals.capacity() * sizeof(Vec3f) +
           mesh_.uvs.capacity() * sizeof(Vec2f) + mesh_.corners.capacity() * sizeof(MeshCorner) +
           mesh_.faceSizes.capacity() * sizeof(uint32_t);
  }

  [[noreturn]] void fail(const std::string &message) const {
    throw SceneError(SourceLocation{name_, line_}, message);
  }

  static bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
  }

  // Splits on whitespace (CR included, so CRLF files parse like LF files).
  static void split(std::string_view s, std::vector<std::string_view> &out) {
    out.clear();
    size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && isSpace(s[i])) ++i;
      size_t start = i;
      while (i < s.size() && !isSpace(s[i])) ++i;
      if (i > start) out.push_back(s.substr(start, i - start));
    }
  }

  double number(std::string_view token) const {
    double v = 0;
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    // from_chars for double is available in libstdc++ 11+.
    auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size())
      fail("expected a number, got '" + std::string(token) + "'");
    if (!std::isfinite(v)) fail("non-finite number '" + std::string(token) + "'");
    // Mesh data is stored in single precision (shared with Embree).
    if (std::fabs(v) > std::numeric_limits<float>::max())
      fail("number '" + std::string(token) + "' is out of range for single precision");
    return v;
  }

  void numbers(const std::vector<std::string_view> &t, size_t minCount, size_t maxCount,
               const char *what, double *out) const {
    size_t n = t.size() - 1;
    if (n < minCount || n > maxCount)
      fail(std::string("'") + what + "' needs " + std::to_string(minCount) +
           (maxCount > minCount ? " to " + std::to_string(maxCount) : std::string()) +
           " numbers, got " + std::to_string(n));
    for (size_t i = 0; i < minCount; ++i) out[i] = number(t[i + 1]);
    for (size_t i = minCount; i < n; ++i) number(t[i + 1]); // validate the rest
  }

  // Resolves a 1-based or negative (relative) OBJ index to 0-based.
  int32_t index(std::string_view token, size_t count, const char *what) const {
    long long v = 0;
    auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size() || v == 0)
      fail(std::string("malformed ") + what + " index '" + std::string(token) + "'");
    long long resolved = v > 0 ? v - 1 : static_cast<long long>(count) + v;
    if (resolved < 0 || resolved >= static_cast<long long>(count))
      fail(std::string(what) + " index " + std::to_string(v) + " is out of range (" +
           std::to_string(count) + " so far)");
    return static_cast<int32_t>(resolved);
  }

  void parseLine(std::string_view line) {
    size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    split(line, tokens_);
    if (tokens_.empty()) return;
    std::string_view kw = tokens_[0];
    double v[4];
    if (kw == "v") {
      // x y z [w] or x y z r g b (vertex colours): position is the first three.
      numbers(tokens_, 3, 7, "v", v);
      mesh_.positions.push_back({float(v[0]), float(v[1]), float(v[2])});
    } else if (kw == "vt") {
      numbers(tokens_, 1, 3, "vt", v);
      mesh_.uvs.push_back({float(v[0]), tokens_.size() > 2 ? float(number(tokens_[2])) : 0.f});
    } else if (kw == "vn") {
      numbers(tokens_, 3, 3, "vn", v);
      mesh_.normals.push_back({float(v[0]), float(v[1]), float(v[2])});
    } else if (kw == "f") {
      if (tokens_.size() < 4)
        fail("face needs at least 3 corners, got " + std::to_string(tokens_.size() - 1));
      for (size_t i = 1; i < tokens_.size(); ++i) mesh_.corners.push_back(corner(tokens_[i]));
      mesh_.faceSizes.push_back(static_cast<uint32_t>(tokens_.size() - 1));
    } else if (kw == "o" || kw == "g" || kw == "s" || kw == "usemtl" || kw == "mtllib" ||
               kw == "l" || kw == "p" || kw == "vp") {
      // Grouping, materials and non-surface elements carry no triangle data.
    } else {
      fail("unknown statement '" + std::string(kw) + "'");
    }
  }

  MeshCorner corner(std::string_view token) const {
    MeshCorner c;
    size_t s1 = token.find('/');
    if (s1 == std::string_view::npos) {
      c.v = index(token, mesh_.positions.size(), "vertex");
      return c;
    }
    c.v = index(token.substr(0, s1), mesh_.positions.size(), "vertex");
    std::string_view rest = token.substr(s1 + 1);
    size_t s2 = rest.find('/');
    std::string_view vt = s2 == std::string_view::npos ? rest : rest.substr(0, s2);
    if (!vt.empty()) c.uv = index(vt, mesh_.uvs.size(), "uv");
    if (s2 != std::string_view::npos) {
      std::string_view vn = rest.substr(s2 + 1);
      if (vn.empty()) fail("malformed face corner '" + std::string(token) + "'");
      c.n = index(vn, mesh_.normals.size(), "normal");
    } else if (vt.empty()) {
      fail("malformed face corner '" + std::string(token) + "'");
    }
    return c;
  }

  std::string name_;
  uint64_t memoryBytes_; ///< the text and the arrays together; 0: no limit
  int line_ = 0;
  MeshSource mesh_;
  std::vector<std::string_view> tokens_;
};

} // namespace

MeshSource parseObj(std::string_view text, const std::string &displayName,
                    uint64_t memoryBytes) {
  ObjParser parser(displayName, memoryBytes);
  parser.parse(text);
  return parser.take();
}

MeshSource loadObj(const std::string &path, const std::string &displayName, uint64_t maxBytes,
                   uint64_t memoryBytes) {
  // A directory reads as an empty file and a device (/dev/zero) never ends:
  // only regular files are OBJ files.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw SceneError(displayName + ": not a regular file (" + path + ")");
  checkFileSize(path, displayName, maxBytes);
  // The text is held whole while it is parsed: it counts against the memory.
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw SceneError(displayName + ": cannot open OBJ file");
  if (memoryBytes && size > memoryBytes)
    throw SceneError(displayName + ": " + std::to_string(size) + " bytes, more than the " +
                     bytesText(memoryBytes) +
                     " the script has left of its memory (raise it with --script-memory)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(displayName + ": cannot open OBJ file");
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (in.bad() || static_cast<uint64_t>(in.gcount()) != size)
    throw SceneError(displayName + ": read error");
  return parseObj(text, displayName, memoryBytes);
}

} // namespace lray
