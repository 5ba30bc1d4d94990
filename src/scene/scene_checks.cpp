// Pipeline: scene description. See scene_checks.h.
#include "scene/scene_checks.h"

#include "util/printable_text.h"

#include <filesystem>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <variant>

namespace lray {

void validateSceneInfo(const SceneInfo &info, uint64_t maxPixels, const std::string &where) {
  SourceLocation loc{where, 0};
  auto positive = [&](int v, const char *name) {
    if (v <= 0)
      throw SceneError(loc, std::string("SceneInfo: ") + name +
                                " must be a positive integer, got " + std::to_string(v));
  };
  positive(info.imageWidth, "image_width");
  positive(info.imageHeight, "image_height");
  positive(info.frames, "frames");
  positive(info.samples, "samples");
  if (!(info.noiseThreshold >= 0) || !std::isfinite(info.noiseThreshold))
    throw SceneError(loc, "SceneInfo: noise_threshold must be a finite number >= 0");
  if (!std::isfinite(info.startClock) || !std::isfinite(info.endClock))
    throw SceneError(loc, "SceneInfo: start_clock and end_clock must be finite numbers");
  // 128-bit-safe: each factor is below 2^31, so do it in long double steps.
  long double pixels = static_cast<long double>(info.imageWidth) * info.imageHeight *
                       info.samples * info.samples;
  if (pixels > static_cast<long double>(maxPixels))
    throw SceneError(loc, "SceneInfo: image_width * image_height * samples^2 = " +
                              readableCount(pixels) + " exceeds the limit of " +
                              readableCount(maxPixels) +
                              " (raise it with --max-pixels)");
}

void checkFileSize(const std::string &path, const std::string &name, uint64_t maxBytes,
                   const char *kind) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > maxBytes)
    throw SceneError(name + ": " + std::to_string(size) + " bytes, more than the limit of " +
                     std::to_string(maxBytes) + kind + " (raise it with --max-file-size)");
}

void validateLightWork(const Scene &scene, uint64_t maxLightSamples) {
  // The samplers count in int: no limit may let a count past it.
  const uint64_t limit = std::min<uint64_t>(maxLightSamples, INT32_MAX);
  for (const SceneLight &light : scene.lights) {
    std::visit(
        [&](const auto &l) {
          const uint64_t n = l.samplesPerPoint();
          if (n <= limit) return;
          throw SceneError(l.loc, std::string(l.kName) + ": " + std::to_string(n) +
                                      " shadow rays per shading point exceed the limit of " +
                                      std::to_string(limit) +
                                      " (raise it with --max-light-samples)");
        },
        light);
  }
}

std::optional<std::string> aspectWarning(const SceneInfo &info, const Camera &camera) {
  double imageAspect = double(info.imageWidth) / info.imageHeight;
  if (std::fabs(camera.aspect - imageAspect) <= 0.01 * imageAspect) return std::nullopt;
  return "camera aspect " + readableNumber(camera.aspect) + " differs from the image's " +
         std::to_string(info.imageWidth) + "/" + std::to_string(info.imageHeight) + " = " +
         readableNumber(imageAspect) + " by more than 1 %: the image will be stretched";
}

} // namespace lray
