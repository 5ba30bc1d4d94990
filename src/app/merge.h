// Pipeline: application. lray-merge: stitches the tiles that `lray --tile`
// and `lray --crop` write (render/tile_file.h) into their frames, exactly
// as one process would have written them.
#pragma once

#include <string>
#include <vector>

namespace lray {

/// What one merge did: frames written, and one message per frame whose
/// tiles are incomplete or do not fit together.
struct MergeResult {
  std::vector<std::string> written; ///< final image paths
  std::vector<std::string> problems;
};

/// Merges every set of tiles in `dir` (grouped by the frame each names);
/// removes a set's tiles once its frame is written unless `keepTiles`.
/// Incomplete sets are left as they are and reported.
MergeResult mergeTiles(const std::string &dir, bool keepTiles);

/// The lray-merge command line: `lray-merge DIR [--keep-tiles] [--quiet]`.
int runMerge(int argc, const char *const *argv);

} // namespace lray
