// Pipeline: shading. Exact shadow skips by shaft culling (Haines and Wallace
// 1994): every shadow ray of a tile towards one light runs inside the
// convex hull of the box around the rays' origins and the box around the
// light's sample points. If no occluder's bounds meet that shaft, no ray
// can be blocked, and none is traced: the image is the same bytes as
// tracing them (tests/shading/shadow_shaft_test.cpp checks both backends).
#pragma once

#include "geometry/bounds.h"
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

  /// Whether no occluder can block a segment from a point of `origins` to
  /// a point of `targets` (both non-empty boxes).
  bool clear(const Bounds3 &origins, const Bounds3 &targets) const;

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
  Vec3 frameOrigin_;
  std::vector<Bounds3> boxes_;    ///< analytic bounded entities, widened by a few ulps
  std::vector<MeshBox> meshes_;
  std::vector<HalfSpace> planes_; ///< unbounded entities (Plane)
};

/// Whether the shaft between boxes a and b (the convex hull of their union)
/// meets box c. Exact for the hull of the two boxes: the hull is the union
/// over s in [0, 1] of the boxes (1 - s) a + s b, so it meets c iff one s
/// satisfies six linear inequalities.
bool shaftMeetsBox(const Bounds3 &a, const Bounds3 &b, const Bounds3 &c);

} // namespace lray
