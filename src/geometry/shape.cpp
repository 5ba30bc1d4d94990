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

// Grazing hits: the ray parameter of a surface met at a small angle moves
// by 1/cos times the rounding of the object-space ray (the double inverse
// matrix applied to an origin 1e4 away is off by an ulp or two of it), so
// there t is refined in long double: the object ray is made exact to long
// double by one step of iterative refinement against worldFromObject (the
// matrix that defines the shape), then Newton steps on the object-space
// quadric, or the plane's exact solution for caps and cube faces. Only
// below this cosine; steeper hits are within a few ulps already (tests/stress).
constexpr double kRefineBelowCosine = 0.5;

using Wide = long double;

struct WideVec {
  Wide x, y, z;
};

/// M^-1 (w - translation) (point) or M^-1 w (vector), corrected once by
/// the residual so its error is that of long double, not of the stored inverse.
WideVec wideObjectSpace(const Transform &xf, const Vec3 &w, bool point) {
  const auto &m = xf.matrix().m;
  const auto &inv = xf.inverseMatrix().m;
  Wide rel[3];
  for (int i = 0; i < 3; ++i) rel[i] = Wide(w[i]) - (point ? Wide(m[i][3]) : Wide(0));
  Wide x[3];
  for (int i = 0; i < 3; ++i)
    x[i] = Wide(inv[i][0]) * rel[0] + Wide(inv[i][1]) * rel[1] + Wide(inv[i][2]) * rel[2];
  Wide r[3];
  for (int i = 0; i < 3; ++i)
    r[i] = rel[i] - (Wide(m[i][0]) * x[0] + Wide(m[i][1]) * x[1] + Wide(m[i][2]) * x[2]);
  for (int i = 0; i < 3; ++i)
    x[i] += Wide(inv[i][0]) * r[0] + Wide(inv[i][1]) * r[1] + Wide(inv[i][2]) * r[2];
  return {x[0], x[1], x[2]};
}

/// The refined t of a hit found at `t` (world-ray units) on part `part`.
double refineHitT(const Entity &entity, const Ray &worldRay, double shift, double t, int part) {
  WideVec o = wideObjectSpace(entity.worldFromObject, worldRay.o, true);
  WideVec d = wideObjectSpace(entity.worldFromObject, worldRay.d, false);
  // Re-origin at the same point as the double test, for conditioning.
  const Wide sh = shift;
  o = {o.x + sh * d.x, o.y + sh * d.y, o.z + sh * d.z};
  Wide s = Wide(t) - sh;
  auto plane = [&](Wide oc, Wide dc, Wide at) { return dc != 0 ? (at - oc) / dc : s; };
  bool quadric = false;
  switch (entity.kind) {
  case ShapeKind::Sphere: quadric = true; break;
  case ShapeKind::Cylinder:
    if (part == 0) quadric = true;
    else s = plane(o.y, d.y, part == 1 ? 0 : 1);
    break;
  case ShapeKind::Cone:
    if (part == 0) quadric = true;
    else s = plane(o.y, d.y, 0);
    break;
  case ShapeKind::Cube: {
    const Wide oc[3] = {o.x, o.y, o.z}, dc[3] = {d.x, d.y, d.z};
    int axis = part / 2;
    s = plane(oc[axis], dc[axis], (part & 1) ? Wide(0.5) : Wide(-0.5));
    break;
  }
  case ShapeKind::Mesh: return t;
  }
  if (quadric) {
    const Wide start = s;
    for (int i = 0; i < 2; ++i) {
      Wide px = o.x + s * d.x, py = o.y + s * d.y, pz = o.z + s * d.z;
      Wide f, df;
      if (entity.kind == ShapeKind::Sphere) {
        f = px * px + py * py + pz * pz - 1;
        df = 2 * (px * d.x + py * d.y + pz * d.z);
      } else if (entity.kind == ShapeKind::Cylinder) {
        f = px * px + pz * pz - 1;
        df = 2 * (px * d.x + pz * d.z);
      } else { // cone: x^2 + z^2 = (1 - y)^2
        Wide k = 1 - py;
        f = px * px + pz * pz - k * k;
        df = 2 * (px * d.x + pz * d.z + k * d.y);
      }
      if (!(df != 0)) break;
      s -= f / df;
    }
    // Newton never leaves the root the double test chose: a step beyond a
    // relative 1e-9 means a degenerate (tangent) configuration; keep t.
    if (!(std::fabs(s - start) <= 1e-9L * (std::fabs(start) + std::fabs(sh))))
      return t;
  }
  double refined = static_cast<double>(s + sh);
  return std::isfinite(refined) ? refined : t;
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

Bounds3 transformedBounds(const Bounds3 &objectBox, const Transform &worldFromObject) {
  if (objectBox.empty()) return objectBox;
  const Bounds3 &o = objectBox;
  Bounds3 world;
  for (int i = 0; i < 8; ++i)
    world.extend(worldFromObject.applyPoint(
        {i & 1 ? o.hi.x : o.lo.x, i & 2 ? o.hi.y : o.lo.y, i & 4 ? o.hi.z : o.lo.z}));
  Vec3 pad = (abs(world.lo) + abs(world.hi)) * 1e-14;
  return {world.lo - pad, world.hi + pad};
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
  if (std::fabs(dot(hit.ng, worldRay.d)) < kRefineBelowCosine * length(worldRay.d)) {
    double t = refineHitT(entity, worldRay, shift, hit.t, oh.part);
    // The refined t decides against tMax (exclusive), so a query bounded by
    // an earlier refined hit of this shape (a backend visiting it twice)
    // does not accept the same point again with its unrefined t. Below
    // tMin the double t stands: the ray may start on the surface.
    if (!(t < worldRay.tMax)) return false;
    if (t > worldRay.tMin) hit.t = t;
  }
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
