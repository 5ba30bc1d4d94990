// Pipeline: acceleration. The scene's unbounded shapes (Plane): no tree can
// bound them, so neither backend puts them in its tree (whose bounds would
// become infinite); both test them on every ray through this one class, so
// the two backends cannot disagree about them either.
#pragma once

#include "math/hit.h"
#include "geometry/shape.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace lray {

class UnboundedShapes {
public:
  UnboundedShapes() = default;
  /// Collects the unbounded entities of `scene` (which must outlive this).
  explicit UnboundedShapes(const Scene &scene) : scene_(&scene) {
    for (uint32_t i = 0; i < scene.entities.size(); ++i)
      if (holds(scene.entities[i])) indices_.push_back(i);
  }

  bool empty() const { return indices_.empty(); }
  size_t size() const { return indices_.size(); }
  /// True for an entity this class tests (the trees leave it out).
  static bool holds(const Entity &e) { return !shapeBounded(e); }

  /// After a tree's closest-hit query that returned `found` (and `hit` if
  /// true): replaces `hit` by a strictly nearer unbounded hit; returns
  /// whether the ray hits anything.
  bool intersect(const Ray &ray, Hit &hit, bool found) const {
    for (uint32_t i : indices_) {
      const double tMax = found ? hit.t : ray.tMax;
      Hit candidate;
      if (!intersectShape(scene_->entities[i], i, ray, tMax, candidate) || !(candidate.t < tMax))
        continue;
      hit = candidate;
      found = true;
    }
    return found;
  }

  /// Whether an unbounded shape lies with t in (ray.tMin, ray.tMax).
  bool occluded(const Ray &ray) const {
    for (uint32_t i : indices_)
      if (occludedShape(scene_->entities[i], ray)) return true;
    return false;
  }

private:
  const Scene *scene_ = nullptr;
  std::vector<uint32_t> indices_;
};

} // namespace lray
