// Pipeline: application. See merge.h.
#include "app/merge.h"

#include "render/tile_file.h"
#include "shading/oiio_library.h"
#include "util/printable_text.h"
#include "util/scene_error.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

namespace lray {

namespace fs = std::filesystem;

namespace {

struct Piece {
  fs::path path;
  TileHeader header;
  int index = -1, count = -1; ///< of a "tile-I-of-N"; -1 for a crop
};

/// At most this many names in one message ("missing a, b, c and 996 more").
constexpr size_t kNamesListed = 5;

/// "tiles overlap at pixel (x, y) ('name')" for the first pixel (tiles in
/// order, each row by row) that an earlier tile holds too, or "".
std::string firstOverlap(const std::vector<Piece> &pieces) {
  // Pairwise for the sets lray makes; a bitmap of the frame for more.
  if (pieces.size() > 2048) {
    const TileHeader &h0 = pieces.front().header;
    std::vector<uint8_t> covered(static_cast<size_t>(h0.fullWidth) * h0.fullHeight, 0);
    for (const Piece &p : pieces) {
      const PixelWindow &w = p.header.window;
      for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
          uint8_t &c = covered[static_cast<size_t>(y) * h0.fullWidth + x];
          if (c)
            return fmt::format("tiles overlap at pixel ({}, {}) ('{}')", x, y,
                               p.path.filename().string());
          c = 1;
        }
    }
    return {};
  }
  for (size_t k = 1; k < pieces.size(); ++k) {
    const PixelWindow &w = pieces[k].header.window;
    int bestX = -1, bestY = -1;
    for (size_t j = 0; j < k; ++j) {
      const PixelWindow &v = pieces[j].header.window;
      const int x0 = std::max(w.x0, v.x0), y0 = std::max(w.y0, v.y0);
      if (x0 >= std::min(w.x1, v.x1) || y0 >= std::min(w.y1, v.y1)) continue;
      if (bestY < 0 || y0 < bestY || (y0 == bestY && x0 < bestX)) bestX = x0, bestY = y0;
    }
    if (bestY >= 0)
      return fmt::format("tiles overlap at pixel ({}, {}) ('{}')", bestX, bestY,
                         pieces[k].path.filename().string());
  }
  return {};
}

/// Stitches one frame's tiles, checked as a set from their headers before
/// the frame is allocated; "" or what is wrong.
std::string mergeFrame(const fs::path &dir, const std::string &finalName,
                       std::vector<Piece> &pieces, bool keepTiles,
                       std::vector<std::string> &written) {
  const TileHeader &h0 = pieces.front().header;
  const std::string first = pieces.front().path.filename().string();
  // Tiles of an N-way split: all N there?
  std::set<int> counts, present;
  for (const Piece &p : pieces)
    if (p.count > 0) {
      counts.insert(p.count);
      present.insert(p.index);
    }
  if (counts.size() > 1)
    return finalName + ": tiles of different splits (--tile I/N with different N)";
  if (counts.size() == 1) {
    const int n = *counts.begin();
    std::string missing;
    size_t listed = 0, more = 0;
    for (int i = 0; i < n; ++i) {
      if (present.count(i)) continue;
      if (listed++ < kNamesListed)
        missing += (missing.empty() ? "" : ", ") + tileFileName(finalName, i, n);
      else ++more;
    }
    if (more) missing += fmt::format(" and {} more", more);
    if (!missing.empty()) return finalName + ": missing " + missing;
  }
  uint64_t area = 0;
  for (const Piece &p : pieces) {
    const TileHeader &h = p.header;
    if (h.fullWidth != h0.fullWidth || h.fullHeight != h0.fullHeight || h.format != h0.format ||
        h.srgb != h0.srgb)
      return finalName + ": tile '" + p.path.filename().string() +
             "' was rendered with another size, format or encoding than '" + first + "'";
    if (h.render != h0.render)
      return finalName + ": tile '" + p.path.filename().string() + "' and '" + first +
             "' come from different renders (another scene file, samples, seed or backend): "
             "render the frame's tiles again with the same scene and options";
    area += static_cast<uint64_t>(h.window.x1 - h.window.x0) * (h.window.y1 - h.window.y0);
  }
  // What the headers claim is checked before the frame is allocated: no
  // two tiles overlap, and together they hold exactly its pixels (a 1 x 1
  // tile cannot claim a huge frame).
  if (std::string overlap = firstOverlap(pieces); !overlap.empty())
    return finalName + ": " + overlap;
  const uint64_t frame = static_cast<uint64_t>(h0.fullWidth) * h0.fullHeight;
  if (area != frame)
    return fmt::format("{}: its tiles hold {} pixels of its {} x {} ({} pixels): render the "
                       "missing windows",
                       finalName, area, h0.fullWidth, h0.fullHeight, frame);
  Film film(h0.fullWidth, h0.fullHeight);
  bool aovs = false;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const Piece &p = pieces[k];
    const Tile tile = readTile(p.path.string()); // one tile's pixels at a time
    if (k == 0 && tile.film.hasAovs()) film.enableAovs();
    if (k == 0) aovs = tile.film.hasAovs();
    if (tile.film.hasAovs() != aovs || !(tile.header.window == p.header.window))
      return finalName + ": tile '" + p.path.filename().string() +
             "' was rendered with other layers than '" + first + "'";
    const PixelWindow &w = p.header.window;
    for (int y = w.y0; y < w.y1; ++y)
      for (int x = w.x0; x < w.x1; ++x) {
        const Film &t = tile.film;
        const int tx = x - w.x0, ty = y - w.y0;
        film.set(x, y, t.get(tx, ty));
        film.setError(x, y, t.error(tx, ty));
        film.setVariance(x, y, t.variance(tx, ty));
        film.setSampleCount(x, y, t.sampleCount(tx, ty));
        if (film.hasAovs()) film.aov(x, y) = t.aov(tx, ty);
      }
  }
  const fs::path out = dir / finalName;
  writeImage(film, out.string(), h0.format, h0.srgb);
  written.push_back(out.string());
  if (!keepTiles)
    for (const Piece &p : pieces) {
      std::error_code ec;
      if (!fs::equivalent(p.path, out, ec)) fs::remove(p.path, ec);
    }
  return {};
}

} // namespace

MergeResult mergeTiles(const std::string &dirName, bool keepTiles) {
  const fs::path dir(dirName);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw SceneError("'" + dirName + "' is not a folder");
  // Any name lray gives a tile: frames whose names start with a dot or
  // hold a newline included (readTileHeader checks the whole name).
  static const std::regex kTileName(
      R"(^[\s\S]+\.(tile-(\d{1,6})-of-(\d{1,6})|crop-\d+-\d+-\d+-\d+)\.exr$)");
  std::map<std::string, std::vector<Piece>> frames;
  MergeResult result;
  std::vector<fs::path> files;
  for (const fs::directory_entry &e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path &file : files) {
    std::smatch m;
    const std::string name = file.filename().string();
    if (!std::regex_match(name, m, kTileName)) continue;
    Piece p;
    p.path = file;
    if (m[2].matched) {
      p.index = std::stoi(m[2]);
      p.count = std::stoi(m[3]);
    }
    try { // a bad tile is named, and the others still merge
      FloatWindow header;
      p.header = readTileHeader(file.string(), header);
    } catch (const std::exception &err) {
      result.problems.push_back(err.what());
      continue;
    }
    frames[p.header.finalName].push_back(std::move(p));
  }
  for (auto &[finalName, pieces] : frames) {
    std::string why;
    try {
      why = mergeFrame(dir, finalName, pieces, keepTiles, result.written);
    } catch (const std::bad_alloc &) {
      why = finalName + ": out of memory";
    } catch (const std::exception &e) { // one frame's failure leaves the others to merge
      why = finalName + ": " + e.what();
    }
    if (!why.empty()) result.problems.push_back(why);
  }
  return result;
}

int runMerge(int argc, const char *const *argv) {
  CLI::App app{"lray-merge stitches the tiles that 'lray --tile I/N' or 'lray --crop' wrote into\n"
               "DIR into their frames (each tile names its frame, format and encoding), the\n"
               "same bytes as a render of the whole frame, and removes the merged tiles.",
               "lray-merge"};
  std::string dir;
  bool keep = false, quiet = false;
  app.add_option("dir", dir, "Folder holding the tiles (the frames are written there)")->required();
  app.add_flag("--keep-tiles", keep, "Leave the tiles after merging");
  app.add_flag("-q,--quiet", quiet, "Print only errors");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    return app.exit(e);
  }
  try {
    MergeResult r = mergeTiles(dir, keep);
    if (!quiet) {
      for (const std::string &w : r.written) std::printf("%s\n", printableText(w).c_str());
      if (r.written.empty() && r.problems.empty())
        std::printf("lray-merge: no tiles in '%s'\n", printableText(dir).c_str());
    }
    for (const std::string &p : r.problems)
      std::fprintf(stderr, "lray-merge: error: %s\n", printableText(p).c_str());
    return r.problems.empty() ? 0 : 1;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "lray-merge: error: %s\n", printableText(e.what()).c_str());
    return 1;
  }
}

} // namespace lray
