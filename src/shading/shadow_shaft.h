// Pipeline: shading. Exact shadow skips by shaft culling (Haines and Wallace
// 1994): a batch of a tile's shadow rays (one light sample each) runs
// inside the convex hull of the box around their origins and the box
// around their ends. If no occluder's bounds meet that shaft, no ray can be
// blocked and none is traced; if only a few analytic shapes do, the rays
// are tested against those alone. Either way the image is the same bytes
// as tracing them (tests/shading/shadow_shaft_test.cpp, both backends).
#pragma once

#include "math/bounds.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <cstddef>
#include <vector>

namespace lray {

class ShadowShafts {
public:
  /// Scenes with more entities than this test no shafts (the test is a
  /// loop over all of them; a large scene's tiles rarely see a clear shaft).
  static constexpr size_t kMaxEntities = 256;

  ShadowShafts() = default;
  explicit ShadowShafts(const Scene &scene);

  bool enabled() const { return enabled_; }

  /// Most candidates tested directly (Candidates::direct).
  static constexpr size_t kMaxDirect = 4;

  /// What may block the segments from points of one box to points of another.
  struct Candidates {
    bool clear = false;  ///< nothing: every segment is clear
    bool direct = false; ///< only the analytic entities listed: test those alone
    size_t count = 0;
    uint32_t entity[kMaxDirect];
  };
  Candidates candidates(const Bounds3 &origins, const Bounds3 &targets) const;
  bool clear(const Bounds3 &origins, const Bounds3 &targets) const {
    return candidates(origins, targets).clear;
  }

  /// blocked[k]: whether one of `c`'s entities blocks rays[k] (c.direct),
  /// for k < n: the same test both backends call for an analytic shape
  /// (occludedAnalytic), with the same ray (a shadow ray's tMax of 1 is
  /// exact in float too), so the answer is theirs; a still sphere's four
  /// rays at once (occludedStillSphereLanes, the same answers).
  void occluded(const Candidates &c, const Ray *rays, size_t n, uint8_t *blocked) const;

private:
  struct HalfSpace {
    Vec3 normal; ///< world normal of a Plane; the solid side is irrelevant
    double offset;
    double magnitude; ///< of its translation: the scale of its own rounding
  };
  /// A mesh: Embree tests its triangles in single precision, relative to
  /// the scene's float frame, so a float ray may stray from the double
  /// segment by about 2^-23 of its coordinates' magnitude there, and an
  /// instanced mesh's float transform moves its vertices by as much of
  /// theirs. The box is widened by both before the test.
  struct MeshBox {
    Bounds3 box;
    double ownPad; ///< 0 for an identity-placed mesh
  };
  bool enabled_ = false;
  const std::vector<Entity> *entities_ = nullptr;
  Vec3 frameOrigin_;
  std::vector<Bounds3> boxes_;    ///< analytic bounded entities, widened by a few ulps
  std::vector<uint32_t> boxEntity_;   ///< the entity of boxes_[i]
  std::vector<uint32_t> planeEntity_; ///< the entity of planes_[i]
  std::vector<uint32_t> unboundedEntity_; ///< unbounded entities but planes (CSG)
  std::vector<MeshBox> meshes_;
  std::vector<HalfSpace> planes_; ///< unbounded entities (Plane)
};

/// The boxes around the origins (`from`) and the ends (o + d: a shadow
/// ray's tMax is 1) of rays[0, n), n > 0. The light loop runs this for
/// every batch of shadow rays: six running bounds of coordinate pairs (x
/// and y of the origins, of the ends; z of both), where twelve doubles kept
/// in memory or spilled from registers chained each ray's update through a
/// store and a load. Each bound is std::min/std::max's choice, in order.
inline void shaftEnds(const Ray *rays, size_t n, Bounds3 &from, Bounds3 &to) {
  using Pair = double __attribute__((vector_size(2 * sizeof(double))));
  auto xyOf = [](const Vec3 &v) { return Pair{v.x, v.y}; };
  const Vec3 end0 = rays[0].o + rays[0].d;
  Pair fromLo = xyOf(rays[0].o), fromHi = fromLo, toLo = xyOf(end0), toHi = toLo;
  Pair zLo = {rays[0].o.z, end0.z}, zHi = zLo;
  for (size_t j = 1; j < n; ++j) {
    const Vec3 &o = rays[j].o;
    const Vec3 end = o + rays[j].d;
    const Pair xy = xyOf(o), endXy = xyOf(end), z = {o.z, end.z};
    fromLo = xy < fromLo ? xy : fromLo;
    fromHi = fromHi < xy ? xy : fromHi;
    toLo = endXy < toLo ? endXy : toLo;
    toHi = toHi < endXy ? endXy : toHi;
    zLo = z < zLo ? z : zLo;
    zHi = zHi < z ? z : zHi;
  }
  from.lo = {fromLo[0], fromLo[1], zLo[0]};
  from.hi = {fromHi[0], fromHi[1], zHi[0]};
  to.lo = {toLo[0], toLo[1], zLo[1]};
  to.hi = {toHi[0], toHi[1], zHi[1]};
}

/// Whether the shaft between boxes a and b (the convex hull of their union)
/// meets box c. Exact for the hull of the two boxes: the hull is the union
/// over s in [0, 1] of the boxes (1 - s) a + s b, so it meets c iff one s
/// satisfies six linear inequalities.
bool shaftMeetsBox(const Bounds3 &a, const Bounds3 &b, const Bounds3 &c);

} // namespace lray
