// Pipeline: geometry. World-space entry points for the analytic shapes
// (shape.h): world rays are taken into object space by the inverse of
// Entity::worldFromObject without renormalising the direction, so t is the
// same parameter in both spaces, and the hit is taken back to world space.
// One switch on ShapeKind, no allocation: both backends call this per ray.
#include "geometry/shape.h"

#include "geometry/affine.h"
#include "geometry/error_bound.h"
#include "geometry/object_shapes.h"

namespace lray {

namespace {

Ray objectRay(const Entity &entity, const Ray &worldRay) {
  const Mat4 &inv = entity.worldFromObject.inverseMatrix();
  return {affinePoint(inv, worldRay.o), affineVector(inv, worldRay.d), worldRay.tMin, worldRay.tMax};
}

// A distant origin makes the quadric coefficients cancel (the cone's
// o.o - (1 - o_y)^2 loses everything at |o| ~ 1e6). Such rays are re-origined
// at their closest approach to the shape's centre before the test: the
// returned t is relative to that point and `shift` gives it back.
constexpr double kFarOrigin = 4;

double farOriginShift(ShapeKind kind, const Ray &ray) {
  Vec3 centre = kind == ShapeKind::Cylinder || kind == ShapeKind::Cone ? Vec3(0, 0.5, 0) : Vec3();
  Vec3 oc = centre - ray.o;
  if (maxAbsComponent(oc) <= kFarOrigin) return 0;
  double dd = dot(ray.d, ray.d);
  return dd > 0 ? dot(oc, ray.d) / dd : 0;
}

Ray shifted(const Ray &ray, double shift) {
  if (shift == 0) return ray;
  return {ray.at(shift), ray.d, ray.tMin - shift, ray.tMax - shift};
}

bool intersectObject(const Entity &entity, const Ray &ray, ObjectHit &hit) {
  switch (entity.kind) {
  case ShapeKind::Sphere: return intersectSphere(ray, hit);
  case ShapeKind::Cylinder: return intersectCylinder(ray, entity.open, hit);
  case ShapeKind::Cone: return intersectCone(ray, entity.open, hit);
  case ShapeKind::Cube: return intersectCube(ray, hit);
  case ShapeKind::Mesh: return false;
  }
  return false;
}

ObjectSurface objectSurface(ShapeKind kind, const Ray &ray, const ObjectHit &hit) {
  switch (kind) {
  case ShapeKind::Sphere: return sphereSurface(ray, hit);
  case ShapeKind::Cylinder: return cylinderSurface(ray, hit);
  case ShapeKind::Cone: return coneSurface(ray, hit);
  case ShapeKind::Cube: return cubeSurface(ray, hit);
  case ShapeKind::Mesh: break;
  }
  return {};
}

// Bounds of the image of the unit disc {x^2 + z^2 <= 1, y = y0}: centre
// M (0, y0, 0), half-extent along world axis i = |(M_i0, M_i2)|.
Bounds3 discBounds(const Mat4 &mat, double y0) {
  const auto &m = mat.m;
  Vec3 c = affinePoint(mat, {0, y0, 0});
  Vec3 e{std::hypot(m[0][0], m[0][2]), std::hypot(m[1][0], m[1][2]), std::hypot(m[2][0], m[2][2])};
  return {c - e, c + e};
}

// Widen by a few double ulps of the coordinates, for the rounding of the
// bound computation itself (backends may then round to float outwards).
Bounds3 padded(const Bounds3 &b) {
  Vec3 pad = (abs(b.lo) + abs(b.hi)) * (8 * kDoubleRoundoff);
  return {b.lo - pad, b.hi + pad};
}

} // namespace

Bounds3 shapeWorldBounds(const Entity &entity) {
  const Mat4 &mat = entity.worldFromObject.matrix();
  const auto &m = mat.m;
  Bounds3 b;
  switch (entity.kind) {
  case ShapeKind::Sphere: {
    // Exact box of an ellipsoid: half-extent along axis i is the norm of
    // row i of the linear part (the support function of the unit ball).
    Vec3 c{m[0][3], m[1][3], m[2][3]};
    Vec3 e{std::sqrt(m[0][0] * m[0][0] + m[0][1] * m[0][1] + m[0][2] * m[0][2]),
           std::sqrt(m[1][0] * m[1][0] + m[1][1] * m[1][1] + m[1][2] * m[1][2]),
           std::sqrt(m[2][0] * m[2][0] + m[2][1] * m[2][1] + m[2][2] * m[2][2])};
    b = Bounds3(c - e, c + e);
    break;
  }
  case ShapeKind::Cylinder: // convex hull of the two end discs
    b = discBounds(mat, 0);
    b.extend(discBounds(mat, 1));
    break;
  case ShapeKind::Cone: // convex hull of the base disc and the apex
    b = discBounds(mat, 0);
    b.extend(affinePoint(mat, {0, 1, 0}));
    break;
  case ShapeKind::Cube:
    for (int i = 0; i < 8; ++i)
      b.extend(affinePoint(mat, {i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5}));
    break;
  case ShapeKind::Mesh:
    return b; // meshes: meshObjectBounds + the backend's instance transform
  }
  return padded(b);
}

bool intersectShape(const Entity &entity, uint32_t entityIndex, const Ray &worldRay, Hit &hit) {
  Ray farRay = objectRay(entity, worldRay);
  double shift = farOriginShift(entity.kind, farRay);
  Ray ray = shifted(farRay, shift);
  ObjectHit oh;
  if (!intersectObject(entity, ray, oh)) return false;
  ObjectSurface s = objectSurface(entity.kind, ray, oh);
  const Transform &xf = entity.worldFromObject;
  hit.t = oh.t + shift;
  hit.entity = entityIndex;
  hit.primitive = 0;
  hit.pObject = s.p;
  hit.p = affinePoint(xf.matrix(), s.p);
  hit.ng = unitVector(affineNormal(xf.inverseMatrix(), s.n));
  hit.ns = hit.ng;
  hit.u = s.u;
  hit.v = s.v;
  hit.pError = hitPointError(xf, s.p, hit.p, 1.0, kDoubleRoundoff, kAnalyticErrorFactor);
  return true;
}

bool occludedShape(const Entity &entity, const Ray &worldRay) {
  Ray ray = objectRay(entity, worldRay);
  ObjectHit oh;
  return intersectObject(entity, shifted(ray, farOriginShift(entity.kind, ray)), oh);
}

} // namespace lray
