// Pipeline: application. See merge.h.
#include "app/merge.h"

#include "render/tile_file.h"
#include "util/scene_error.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

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
  int index = -1, count = -1; ///< from "tile-I-of-N"; -1 for a crop
  Tile tile;
};

/// Stitches one frame's tiles; "" or what is wrong.
std::string mergeFrame(const fs::path &dir, const std::string &finalName, std::vector<Piece> &pieces,
                       bool keepTiles, std::vector<std::string> &written) {
  const TileHeader &h0 = pieces.front().tile.header;
  // Tiles of an N-way split: all N there?
  std::set<int> counts, present;
  for (const Piece &p : pieces)
    if (p.count > 0) {
      counts.insert(p.count);
      present.insert(p.index);
    }
  if (counts.size() > 1) return finalName + ": tiles of different splits (--tile I/N with different N)";
  if (counts.size() == 1) {
    const int n = *counts.begin();
    std::string missing;
    for (int i = 0; i < n; ++i)
      if (!present.count(i)) missing += (missing.empty() ? "" : ", ") + tileFileName(finalName, i, n);
    if (!missing.empty()) return finalName + ": missing " + missing;
  }
  for (const Piece &p : pieces) {
    const TileHeader &h = p.tile.header;
    if (h.fullWidth != h0.fullWidth || h.fullHeight != h0.fullHeight || h.format != h0.format ||
        h.srgb != h0.srgb || p.tile.film.hasAovs() != pieces.front().tile.film.hasAovs())
      return finalName + ": tile '" + p.path.filename().string() +
             "' was rendered with another size, format or encoding than '" +
             pieces.front().path.filename().string() + "'";
    if (h.render != h0.render)
      return finalName + ": tile '" + p.path.filename().string() + "' and '" +
             pieces.front().path.filename().string() +
             "' come from different renders (another scene file, samples, seed or backend): "
             "render the frame's tiles again with the same scene and options";
  }
  Film film(h0.fullWidth, h0.fullHeight);
  if (pieces.front().tile.film.hasAovs()) film.enableAovs();
  std::vector<uint8_t> covered(film.pixels(), 0);
  for (const Piece &p : pieces) {
    const PixelWindow &w = p.tile.header.window;
    for (int y = w.y0; y < w.y1; ++y)
      for (int x = w.x0; x < w.x1; ++x) {
        uint8_t &c = covered[static_cast<size_t>(y) * film.width() + x];
        if (c) return fmt::format("{}: tiles overlap at pixel ({}, {}) ('{}')", finalName, x, y,
                                  p.path.filename().string());
        c = 1;
        const Film &t = p.tile.film;
        const int tx = x - w.x0, ty = y - w.y0;
        film.set(x, y, t.get(tx, ty));
        film.setError(x, y, t.error(tx, ty));
        film.setSampleCount(x, y, t.sampleCount(tx, ty));
        if (film.hasAovs()) film.aov(x, y) = t.aov(tx, ty);
      }
  }
  for (size_t i = 0; i < covered.size(); ++i)
    if (!covered[i])
      return fmt::format("{}: no tile holds pixel ({}, {}): render the missing window", finalName,
                         i % film.width(), i / film.width());
  const fs::path out = dir / finalName;
  writeImage(film, out.string(), h0.format, h0.srgb);
  written.push_back(out.string());
  if (!keepTiles)
    for (const Piece &p : pieces) {
      std::error_code ec;
      fs::remove(p.path, ec);
    }
  return {};
}

} // namespace

MergeResult mergeTiles(const std::string &dirName, bool keepTiles) {
  const fs::path dir(dirName);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw SceneError("'" + dirName + "' is not a folder");
  static const std::regex kTileName(R"(^[^.].*\.(tile-(\d{1,6})-of-(\d{1,6})|crop-\d+-\d+-\d+-\d+)\.exr$)");
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
    try {
      p.tile = readTile(file.string());
    } catch (const SceneError &err) {
      result.problems.push_back(err.what());
      continue;
    }
    frames[p.tile.header.finalName].push_back(std::move(p));
  }
  for (auto &[finalName, pieces] : frames) {
    std::string why;
    try {
      why = mergeFrame(dir, finalName, pieces, keepTiles, result.written);
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
      for (const std::string &w : r.written) std::printf("%s\n", w.c_str());
      if (r.written.empty() && r.problems.empty()) std::printf("lray-merge: no tiles in '%s'\n", dir.c_str());
    }
    for (const std::string &p : r.problems) std::fprintf(stderr, "lray-merge: error: %s\n", p.c_str());
    return r.problems.empty() ? 0 : 1;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "lray-merge: error: %s\n", e.what());
    return 1;
  }
}

} // namespace lray
