// Pipeline: render. What one frame is rendered at, and how progress is
// reported; shared by the renderer and the backends that run its tile loop.
#pragma once

#include <cstddef>
#include <functional>

namespace lray {

struct FrameSettings {
  int width = 800;
  int height = 600;
  int samples = 1;    ///< n: n x n stratified jittered samples per pixel
  int frameIndex = 0; ///< part of the random-stream key
};

/// Called after each finished tile with (tiles done, tiles total), from
/// worker threads: must be thread-safe.
using ProgressFn = std::function<void(size_t, size_t)>;

constexpr int kTileSize = 16;

} // namespace lray
