// Pipeline: geometry. See float_frame.h.
#include "geometry/float_frame.h"

#include "math/error_bound.h"
#include "geometry/shape.h"

#include <unordered_map>

namespace lray {

namespace {

/// World bounds of the scene's entities (meshes through their object box's
/// corners); non-finite boxes are left out.
Bounds3 sceneBounds(const Scene &scene) {
  Bounds3 all;
  std::unordered_map<const MeshData *, Bounds3> meshBoxes;
  for (const Entity &e : scene.entities) {
    Bounds3 b;
    if (e.isMesh()) {
      if (!e.mesh) continue;
      auto [it, added] = meshBoxes.try_emplace(e.mesh.get());
      if (added) it->second = meshObjectBounds(*e.mesh);
      b = transformedBounds(it->second, e.worldFromObject);
    } else {
      b = shapeWorldBounds(e);
    }
    if (!b.empty() && isFinite(b.lo) && isFinite(b.hi)) {
      all.extend(b.lo);
      all.extend(b.hi);
    }
  }
  return all;
}

} // namespace

Vec3 floatFrameOrigin(const Scene &scene) {
  Vec3 eye = scene.camera.worldFromCamera.applyPoint({0, 0, 0});
  if (!isFinite(eye)) return {0, 0, 0};
  Bounds3 b = sceneBounds(scene);
  Vec3 at = eye;
  if (!b.empty()) at = max(b.lo, min(eye, b.hi));
  if (!(maxAbsComponent(at) > kFloatFrameThreshold)) return {0, 0, 0};
  // The empty asm keeps each rounded float in a register as a float: GCC 12
  // at -O2 vectorizes a (double)(float) round trip of two components and
  // drops the conversion (this function returned the unrounded point).
  Vec3 origin;
  for (int i = 0; i < 3; ++i) {
    float rounded = static_cast<float>(at[i]);
    asm("" : "+x"(rounded));
    origin[i] = rounded;
  }
  return origin;
}

} // namespace lray
