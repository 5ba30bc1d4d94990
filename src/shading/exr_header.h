// Pipeline: shading (image files). A look at an EXR file's header before
// OpenEXR opens it. OpenEXR sizes its buffers (the table of chunk offsets,
// line buffers) and OpenImageIO its pixels by what the header claims, so a
// 1 KiB file claiming a 16384 x 16384 data window would cost gigabytes
// before the missing data is noticed. Read here from the header's own
// bytes (the layout is OpenEXR's documented file format), those claims
// are checked against the file's size first: what LRay writes (lossless,
// scanline, one part) passes; a file that could not hold what it claims
// is refused.
#pragma once

#include <cstdint>
#include <string>

namespace lray {

struct ExrHeaderLimits {
  uint64_t maxPixels; ///< of the data window and of the display window
  int maxChannels;
};

/// "" when the EXR at `path` is a single-part scanline image, losslessly
/// compressed (none, RLE, ZIPS, ZIP, PIZ), with windows of at most
/// `maxPixels` pixels, 1 to `maxChannels` unsampled channels, and a size
/// that can hold its chunk table and (compressed at most 8192:1) its
/// pixels; else why not, as a phrase ("its header claims ...").
std::string checkExrHeader(const std::string &path, const ExrHeaderLimits &limits);

} // namespace lray
