// Pipeline: geometry. The shapes' own intersection code, shared by both
// backends: Embree's user-geometry callbacks and the kd-tree both call these,
// so the two cannot disagree about a shape.
#pragma once

#include "math/bounds.h"
#include "math/hit.h"
#include "geometry/shapes/span.h"
#include "math/ray.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>

namespace lray {

/// Tight world-space bounds of an analytic entity (every shape but Mesh;
/// infinite for the unbounded ones); a moving one's over the shutter times
/// [t0, t1] (Entity::motion).
Bounds3 shapeWorldBounds(const Entity &entity, double t0 = 0, double t1 = 1);

/// False for shapes without finite bounds (Plane): the backends keep those
/// out of their trees and test them on every ray (accel/unbounded_shapes.h).
bool shapeBounded(const Entity &entity);

/// Closest intersection of a world-space ray with an analytic entity, with t
/// in (ray.tMin, tMax), the entity placed where it is at the ray's time.
/// On success fills every field of `hit` (entity = entityIndex) and returns
/// true; otherwise leaves `hit` as it was (a caller may pass its best hit).
/// The bound is its own argument (usually below ray.tMax: the nearest hit
/// so far) so that callers need not copy the ray to lower it: the test's
/// reads of a copy just written in other pieces stalled on store
/// forwarding.
bool intersectShape(const Entity &entity, uint32_t entityIndex, const Ray &worldRay, double tMax,
                    Hit &hit);

/// Any intersection with t in (ray.tMin, tMax).
bool occludedShape(const Entity &entity, const Ray &worldRay, double tMax);

/// occludedShape for an entity that is a Sphere without motion, the same
/// test without the dispatch on its shape: a backend's callback for
/// thousands of spheres' shadow rays.
bool occludedStillSphere(const Entity &entity, const Ray &worldRay, double tMax);

/// intersectShape of four rays at once on a still sphere (isStillSphere):
/// for each lane k in `open`, rays[k] against the entity before tMax[k];
/// bit k of the result set where it hits, and *hits[k] then holds the hit
/// intersectShape gives, bit for bit (untouched elsewhere). Rays of lanes
/// outside `open` are read but not used (any ray will do).
uint32_t intersectStillSphereLanes(const Entity &entity, uint32_t entityIndex,
                                   const Ray *const (&rays)[4], const double (&tMax)[4],
                                   uint32_t open, Hit *const (&hits)[4]);

/// occludedStillSphere of four rays at once: bit k set where rays[k] is
/// blocked before tMax[k] (the same answers).
uint32_t occludedStillSphereLanes(const Entity &entity, const Ray *const (&rays)[4],
                                  const double (&tMax)[4]);

/// Whether occludedStillSphere may test `entity`.
inline bool isStillSphere(const Entity &entity) {
  return !entity.motion && std::holds_alternative<Sphere>(entity.shape);
}

/// The two above within the ray's own bounds.
inline bool intersectShape(const Entity &entity, uint32_t entityIndex, const Ray &worldRay,
                           Hit &hit) {
  return intersectShape(entity, entityIndex, worldRay, worldRay.tMax, hit);
}
inline bool occludedShape(const Entity &entity, const Ray &worldRay) {
  return occludedShape(entity, worldRay, worldRay.tMax);
}

/// Whether an analytic entity blocks `worldRay` within its bounds, by the
/// test a backend calls for it (occludedStillSphere for a still sphere,
/// occludedShape otherwise; the same answer either way): so a shadow ray
/// tested against one entity alone is blocked there exactly when a backend
/// would find that entity blocking it.
inline bool occludedAnalytic(const Entity &entity, const Ray &worldRay) {
  return isStillSphere(entity) ? occludedStillSphere(entity, worldRay, worldRay.tMax)
                               : occludedShape(entity, worldRay);
}

/// The stretches of the whole line of `worldRay` inside a solid primitive
/// (a CSG leaf; 0 for Mesh and CSG), in order: parameters of the entity's
/// object ray re-origined by `shift` (world t = t + shift).
int shapeSpans(const Entity &entity, const Ray &worldRay, Span *out, double &shift);

/// intersectShape's hit at a crossing shapeSpans found: `tObject` and
/// `part` as it gave them. False when the refined t reaches ray.tMax.
bool fillShapeHit(const Entity &entity, uint32_t entityIndex, const Ray &worldRay, double tObject,
                  int part, Hit &hit);

/// Object-space bounds of a mesh (positions as stored).
Bounds3 meshObjectBounds(const MeshData &mesh);

/// `worldRay` (its time kept) in the object space of `entity`, placed where
/// it is at the ray's time: the same parameter t in both spaces.
Ray objectSpaceRay(const Entity &entity, const Ray &worldRay);

/// World bounds of a mesh entity over the shutter times [t0, t1]: its
/// vertices at every motion step (Entity::vertexMotion) placed by its
/// transform, or swept by its motion (Entity::motion).
Bounds3 meshWorldBounds(const Entity &entity, double t0 = 0, double t1 = 1);

/// World bounds of a moving entity (analytic or mesh) at motion step
/// `step`, such that the linear blend of neighbouring steps' bounds holds
/// it at every time between them (TransformMotion::stepBounds; a CSG's
/// bounds over the whole shutter at every step).
Bounds3 stepWorldBounds(const Entity &entity, size_t step);

/// World bounds of an object-space box placed by `worldFromObject`: its
/// eight corners transformed, widened by a few ulps for the rounding of the
/// transform. An empty box stays empty.
Bounds3 transformedBounds(const Bounds3 &objectBox, const Transform &worldFromObject);

/// Fills `hit` for triangle `triangle` of mesh entity `entity` hit at
/// parameter t of the world ray, with barycentrics (b1, b2) of corners 1 and 2
/// (corner 0 has 1 - b1 - b2): interpolated normals when smooth, uvs
/// (given or the default per-triangle mapping), object and world points.
/// Used by both backends after their triangle test. `frameOrigin` is the
/// scene's floatFrameOrigin (float_frame.h): pError covers the rounding of
/// a single-precision backend working relative to it.
void fillTriangleHit(const Entity &entity, uint32_t entityIndex, uint32_t triangle, double t,
                     double b1, double b2, const Ray &worldRay, const Vec3 &frameOrigin,
                     Hit &hit);

/// The point of mesh triangle `triangle` at barycentrics (b1, b2), placed
/// where its entity is at shutter time `time`, and its unit geometric
/// normal as fillTriangleHit gives a hit there (on the side the vertex
/// normals say is outside): points drawn on emitting meshes.
void triangleSurfacePoint(const Entity &entity, uint32_t triangle, double b1, double b2,
                          float time, Vec3 &p, Vec3 &ng);

/// A triangle of a mesh entity that does not move, ready to have many
/// points drawn on it: triangleSurfacePoint's results, bit for bit, from
/// corners read once and, where the vertex normals put every point's
/// normal on the same side, a normal computed once.
class FixedTriangle {
public:
  FixedTriangle(const Entity &entity, uint32_t triangle);
  void surfacePoint(double b1, double b2, Vec3 &p, Vec3 &ng) const;

private:
  const Entity *entity_;
  uint32_t triangle_;
  bool constantNormal_ = false;
  Vec3 corner_[3]; ///< object space
  Vec3 ng_;        ///< when constantNormal_
};

/// One mesh hit to fill: fillTriangleHit's arguments.
struct TriangleHitQuery {
  const Entity *entity;
  uint32_t entityIndex;
  uint32_t triangle;
  double t, b1, b2;
  const Ray *ray;
  Hit *hit;
};

/// fillTriangleHit for each query (the same Hits, bit for bit), identity-
/// placed meshes several at a time in SIMD lanes when `frameOrigin` is the
/// world origin (triangle_hits.cpp).
void fillTriangleHits(const TriangleHitQuery *queries, size_t count, const Vec3 &frameOrigin);

namespace detail {
/// fillTriangleHits with the lane code chosen (avx2: the AVX2 variant, which
/// needs a CPU that has it); for tests.
void fillTriangleHits(const TriangleHitQuery *queries, size_t count, const Vec3 &frameOrigin,
                      bool avx2);
} // namespace detail

} // namespace lray
