// Pipeline: scene description. A mesh whose vertices move while the shutter
// is open (lua/README.md, "Motion blur"): the same triangles with their
// positions and normals at each motion step, interpolated linearly between
// the steps (as Embree's motion-blurred triangles are).
#pragma once

#include "math/bounds.h"
#include "math/motion_steps.h"
#include "scene/mesh_data.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace lray {

struct MeshMotion {
  /// The mesh at each motion step, steps[0] the entity's own; the same
  /// triangles (corner indices) in each.
  std::vector<MeshDataPtr> steps;

  /// Vertex `v` at shutter time `time` in [0, 1].
  Vec3 position(uint32_t v, double time) const {
    size_t i;
    double u;
    locateMotionStep(time, steps.size(), i, u);
    return lerp(steps[i]->positions[v], steps[i + 1]->positions[v], u);
  }
  /// Normal `n` (an index into MeshData::normals) at `time`, not normalised.
  Vec3 normal(uint32_t n, double time) const {
    size_t i;
    double u;
    locateMotionStep(time, steps.size(), i, u);
    return lerp(steps[i]->normals[n], steps[i + 1]->normals[n], u);
  }
  /// Bounds of triangle `t` at every time: of its corners at every step
  /// (each corner moves in straight lines between them).
  Bounds3 triangleBounds(uint32_t t) const {
    Bounds3 b;
    for (const MeshDataPtr &m : steps)
      for (int k = 0; k < 3; ++k)
        b.extend(toVec3(m->positions[m->triangleIndices[3 * size_t{t} + k]]));
    return b;
  }

  /// Bounds of every vertex at every step.
  Bounds3 bounds() const {
    Bounds3 b;
    for (const MeshDataPtr &m : steps)
      for (const Vec3f &p : m->positions)
        b.extend(toVec3(p));
    return b;
  }

private:
  static Vec3 lerp(const Vec3f &a, const Vec3f &b, double u) {
    return toVec3(a) * (1 - u) + toVec3(b) * u;
  }
};

} // namespace lray
