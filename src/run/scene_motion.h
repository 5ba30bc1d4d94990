// Pipeline: run. Motion blur from the clock (lua/README.md,
// "Motion blur"): the scenes scene(clock) returned at the k motion steps of
// a frame's open shutter become one scene whose moving parts carry their
// placement at every step (Entity::motion, Camera::motion, LightMotion).
#pragma once

#include "scene/scene.h"

#include <vector>

namespace lray {

/// The clock values of frame `frame`'s motion steps: info.motionSteps of
/// them, evenly spread from the frame's clock over the open shutter
/// (info.shutter of the interval to the next frame's clock). One value,
/// the frame's clock, without motion blur (shutter 0, or no interval).
std::vector<double> motionClocks(const SceneInfo &info, int frame);

/// Folds `steps[1..]` into `steps[0]` (returned): entities and lights are
/// matched by the order they were added; those whose placement changes get
/// their motion, the camera too. Throws SceneError naming the first
/// mismatch and the two clock values where the scenes do not match: a
/// different count or kind of entity or light, a shape parameter that
/// changes (a Torus's radii), a mesh whose triangles change (its vertices
/// and normals may move: Entity::vertexMotion), a CSG whose operators or
/// parts change (its parts may move, each by its own transform).
Scene foldMotionSteps(std::vector<Scene> steps, const std::vector<double> &clocks);

} // namespace lray
