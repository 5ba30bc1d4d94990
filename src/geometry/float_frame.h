// Pipeline: geometry. The single-precision frame of a frame's geometry.
// Embree traces float rays against float vertices; far from the world's
// origin a float cannot tell two points 1e-3 apart (at 1e5 its spacing is
// 0.008), so a scene moved there would shadow itself or leak shadows.
// Scenes far from the origin are therefore handed to Embree relative to a
// frame origin near the eye ("camera-relative" coordinates): every
// subtraction happens in double before rounding to float, so the precision
// near the viewer is that of a scene at the origin. Hit points, normals and
// rays stay in world space (double) everywhere else; only the float copies
// and the spawn-offset error bound (fillTriangleHit) see the frame.
#pragma once

#include "geometry/error_bound.h"
#include "scene/scene.h"

namespace lray {

/// Below this magnitude of the eye's coordinates the frame stays at the
/// world origin: float spacing there is at most 2^-13 of a unit, and scenes
/// near the origin keep their vertex buffers shared with Embree (no copy).
constexpr double kFloatFrameThreshold = 1024;

/// The frame origin for `scene`: the eye's position rounded to float (so
/// float vertices near it subtract exactly), or the world origin when the
/// eye is within kFloatFrameThreshold of it on every axis.
inline Vec3 floatFrameOrigin(const Scene &scene) {
  Vec3 eye = scene.camera.worldFromCamera.applyPoint({0, 0, 0});
  if (!(maxAbsComponent(eye) > kFloatFrameThreshold) || !std::isfinite(maxAbsComponent(eye)))
    return {0, 0, 0};
  // The empty asm keeps each rounded float in a register as a float: GCC 12
  // at -O2 vectorizes the (double)(float) round trip of x and y and drops
  // the conversion (the function returned the unrounded eye).
  Vec3 origin;
  for (int i = 0; i < 3; ++i) {
    float rounded = static_cast<float>(eye[i]);
    asm("" : "+x"(rounded));
    origin[i] = rounded;
  }
  return origin;
}

} // namespace lray
