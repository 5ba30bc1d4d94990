// Tests for run/frame_pipeline: a frame rendered with one thread allowed
// (lray -t 1) starts no thread of its own, and one with two renders the
// same picture.
#include "bindings/scene_script.h"
#include "run/frame_pipeline.h"
#include "shading/image_cache.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <filesystem>

namespace lray {
namespace {

constexpr const char *kScene = R"lua(
scene_info = SceneInfo() { image_width = 48, image_height = 32 }
function scene(clock)
  local s = Scene() { camera = Perspective(45, 1.5) { transform = Translate(-4 * z) } }
  s:add_entity(Floor())
  s:add_entity(Sphere(Translate(Vector(0, 1, 0))))
  s:add_light(Light() { transform = Translate(Vector(-3, 5, -4)) })
  return s
end
)lua";

/// The threads of this process (Linux: one entry each in /proc/self/task).
size_t threadCount() {
  size_t n = 0;
  for ([[maybe_unused]] const auto &entry : std::filesystem::directory_iterator("/proc/self/task"))
    ++n;
  return n;
}

/// The frame rendered with at most `threads` threads, and how many threads
/// the render started (counted while the limit holds: lifting it lets TBB
/// start its workers).
Film renderWith(size_t threads, const char *backend, size_t &started) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  // The script's watchdog thread starts with the script.
  SceneScript script = SceneScript::fromString(kScene, "pipeline.lua");
  ImageCache images(false);
  FrameStats stats;
  const size_t before = threadCount();
  Film film = renderScriptFrame(script, script.info(), 0, backend, images, stats);
  started = threadCount() - before;
  return film;
}

TEST(FramePipeline, OneThreadAllowedStartsNoOtherThread) {
  // A TBB worker an earlier test started would be reused unseen: the
  // check needs the suite's own process (ctest runs each suite alone). The
  // kd-tree: Embree's device starts threads of its own.
  size_t started = 0;
  const Film one = renderWith(1, "kdtree", started);
  EXPECT_EQ(started, 0u);
  EXPECT_EQ(renderWith(2, "kdtree", started).data(), one.data());
}

} // namespace
} // namespace lray
