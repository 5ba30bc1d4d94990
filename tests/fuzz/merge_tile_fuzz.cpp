// Fuzz target (libFuzzer): lray-merge's tile reader. The input bytes are a
// file under a tile's name (seeded with a real 16 x 16 tile that lray
// wrote, tests/fuzz/seeds/merge_tile): readTileHeader checks it before any
// pixel is decoded, then readTile reads it whole. A SceneError (not an LRay
// tile, a header that claims too much, a name that is not its own) is the
// expected refusal; a crash, a sanitizer report, another exception, an
// allocation past the header's checks or a film that disagrees with its
// header is a bug.
#include "render/tile_file.h"
#include "shading/oiio_library.h"
#include "util/scene_error.h"

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

/// A folder of this process's own in memory (/dev/shm) when there is one.
const std::string &tilePath() {
  static const std::string path = [] {
    namespace fs = std::filesystem;
    const fs::path base = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    const fs::path dir = base / ("lray_merge_fuzz_" + std::to_string(getpid()));
    fs::create_directories(dir);
    return (dir / "seed.tile-0-of-1.exr").string();
  }();
  return path;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string &path = tilePath();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char *>(data), static_cast<std::streamsize>(size));
  }
  try {
    lray::FloatWindow header;
    const lray::TileHeader h = lray::readTileHeader(path, header);
    check(h.fullWidth > 0 && h.fullHeight > 0);
    const lray::Tile tile = lray::readTile(path);
    const lray::PixelWindow &w = tile.header.window;
    check(tile.film.width() == w.x1 - w.x0 && tile.film.height() == w.y1 - w.y0);
    check(w.x0 >= 0 && w.y0 >= 0 && w.x1 <= h.fullWidth && w.y1 <= h.fullHeight);
  } catch (const lray::SceneError &) {
  }
  return 0;
}
