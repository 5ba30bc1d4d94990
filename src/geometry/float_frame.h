// Pipeline: geometry. The single-precision frame of a frame's geometry.
// Embree traces float rays against float vertices; far from the world's
// origin a float cannot tell two points 1e-3 apart (at 1e5 its spacing is
// 0.008), so a scene moved there would shadow itself or leak shadows.
// Scenes far from the origin are therefore handed to Embree relative to a
// frame origin where the viewer looks from ("camera-relative"
// coordinates): every subtraction happens in double before rounding to
// float, so the precision there is that of a scene at the origin. Hit
// points, normals and rays stay in world space (double) everywhere else;
// only the float copies and the spawn-offset error bound (fillTriangleHit)
// see the frame.
#pragma once

#include "scene/scene.h"

namespace lray {

/// Below this magnitude of the frame origin's coordinates the frame stays
/// at the world origin: float spacing there is at most 2^-13 of a unit,
/// and scenes near the origin keep their vertex buffers shared with Embree
/// (no copy).
constexpr double kFloatFrameThreshold = 1024;

/// The frame origin for `scene`: the point of the scene's bounding box
/// nearest to the eye (the eye itself when it is inside the box: a camera
/// in a large scene; the near side of the box for a telephoto view of a
/// distant object), rounded to float so that float vertices near it
/// subtract exactly; the world origin when that point is within
/// kFloatFrameThreshold of it on every axis. O(entities + mesh vertices).
Vec3 floatFrameOrigin(const Scene &scene);

} // namespace lray
