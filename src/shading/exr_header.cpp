// Pipeline: shading (image files). See exr_header.h. The file format:
// 4 bytes of magic, 4 of version and flags, then attributes (name,
// type name, both NUL-terminated, a 32-bit little-endian size, the value)
// up to an empty name; then the chunk offset table (8 bytes per chunk) and
// the chunks.
#include "shading/exr_header.h"

#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <string_view>
#include <vector>

namespace lray {

namespace {

constexpr size_t kMaxHeaderBytes = size_t{1} << 20; // LRay's are under 2 KiB
constexpr uint64_t kMaxCompression = 8192;          // zlib's deflate stops near 1032:1

struct Box {
  int64_t xMin = 0, yMin = 0, xMax = -1, yMax = -1;
  int64_t width() const { return xMax - xMin + 1; }
  int64_t height() const { return yMax - yMin + 1; }
};

class Reader {
public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  bool cString(std::string_view &s) {
    const size_t end = bytes_.find('\0', pos_);
    if (end == std::string_view::npos || end - pos_ > 255) return false;
    s = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return true;
  }
  bool int32(int64_t &v) {
    if (bytes_.size() - pos_ < 4) return false;
    uint32_t u = 0;
    for (int i = 3; i >= 0; --i)
      u = (u << 8) | uint8_t(bytes_[pos_ + size_t(i)]);
    v = int32_t(u);
    pos_ += 4;
    return true;
  }
  bool bytes(size_t n, std::string_view &out) {
    if (bytes_.size() - pos_ < n) return false;
    out = bytes_.substr(pos_, n);
    pos_ += n;
    return true;
  }
  size_t position() const { return pos_; }

private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

bool readBox(std::string_view value, Box &box) {
  Reader r(value);
  return value.size() == 16 && r.int32(box.xMin) && r.int32(box.yMin) && r.int32(box.xMax) &&
         r.int32(box.yMax);
}

/// The channels' count and bytes per pixel; false when one is subsampled
/// or of an unknown type.
bool readChannels(std::string_view value, int &count, int64_t &bytesPerPixel) {
  Reader r(value);
  count = 0;
  bytesPerPixel = 0;
  for (;;) {
    std::string_view name;
    if (!r.cString(name)) return false;
    if (name.empty()) return r.position() == value.size();
    int64_t type = 0, xSampling = 0, ySampling = 0;
    std::string_view linearAndReserved;
    if (!r.int32(type) || !r.bytes(4, linearAndReserved) || !r.int32(xSampling) ||
        !r.int32(ySampling))
      return false;
    if (type < 0 || type > 2 || xSampling != 1 || ySampling != 1) return false;
    bytesPerPixel += type == 1 ? 2 : 4; // HALF; UINT and FLOAT
    ++count;
  }
}

/// Scanlines per chunk of the lossless compressions; 0 for the others.
int linesPerChunk(int compression) {
  switch (compression) {
  case 0: // none
  case 1: // RLE
  case 2: // ZIPS
    return 1;
  case 3: // ZIP
    return 16;
  case 4: // PIZ
    return 32;
  default:
    return 0;
  }
}

} // namespace

std::string checkExrHeader(const std::string &path, const ExrHeaderLimits &limits) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "cannot open it";
  const uint64_t fileSize = uint64_t(st.st_size);
  std::vector<char> buffer(std::min<uint64_t>(fileSize, kMaxHeaderBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in.read(buffer.data(), std::streamsize(buffer.size()))) return "cannot read it";
  Reader r(std::string_view(buffer.data(), buffer.size()));
  std::string_view magic;
  int64_t version = 0;
  if (!r.bytes(4, magic) || magic != std::string_view("\x76\x2f\x31\x01", 4) || !r.int32(version))
    return "not an EXR file";
  // Version 2; flags: 0x200 tiled, 0x400 long names, 0x800 deep, 0x1000 multi-part.
  if ((version & 0xff) != 2 || (version & ~int64_t(0x4ff)) != 0)
    return "not a single-part scanline EXR (as LRay writes them)";
  Box data, display;
  bool haveData = false, haveDisplay = false, haveChannels = false;
  int channels = 0, compression = -1;
  int64_t bytesPerPixel = 0;
  for (;;) {
    std::string_view name, type, value;
    int64_t size = 0;
    if (!r.cString(name)) return "its header is cut short";
    if (name.empty()) break;
    if (!r.cString(type) || !r.int32(size) || size < 0 || !r.bytes(size_t(size), value))
      return "its header is cut short or malformed";
    if (name == "dataWindow" && type == "box2i")
      haveData = readBox(value, data);
    else if (name == "displayWindow" && type == "box2i")
      haveDisplay = readBox(value, display);
    else if (name == "channels" && type == "chlist")
      haveChannels = readChannels(value, channels, bytesPerPixel);
    else if (name == "compression" && type == "compression" && value.size() == 1)
      compression = uint8_t(value[0]);
  }
  if (!haveData || !haveDisplay || !haveChannels || compression < 0)
    return "its header lacks or garbles its windows, channels or compression";
  for (const Box *b : {&data, &display}) {
    // Each side checked at most 2^31 first: the product cannot overflow.
    if (b->width() <= 0 || b->height() <= 0 || b->width() > (int64_t{1} << 31) ||
        b->height() > (int64_t{1} << 31) ||
        uint64_t(b->width()) * uint64_t(b->height()) > limits.maxPixels)
      return "its header claims a window of " + std::to_string(b->width()) + " x " +
             std::to_string(b->height()) + " pixels, more than LRay reads";
  }
  if (channels < 1 || channels > limits.maxChannels)
    return std::to_string(channels) + " channels, more than LRay reads";
  const int lines = linesPerChunk(compression);
  if (lines == 0) return "not losslessly compressed (as LRay writes them)";
  const uint64_t chunks = (uint64_t(data.height()) + uint64_t(lines) - 1) / uint64_t(lines);
  const uint64_t raw = uint64_t(data.width()) * uint64_t(data.height()) * uint64_t(bytesPerPixel);
  // A chunk: its offset in the table, its line number and size (8 bytes),
  // and at least a byte of data.
  const uint64_t least = r.position() + chunks * 17 + raw / kMaxCompression;
  if (fileSize < least)
    return "its header claims " + std::to_string(data.width()) + " x " +
           std::to_string(data.height()) + " pixels, more than its " + std::to_string(fileSize) +
           " bytes can hold";
  return {};
}

} // namespace lray
