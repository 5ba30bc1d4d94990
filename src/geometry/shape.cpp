// Pipeline: geometry. World-space entry points for the analytic shapes
// (shape.h), written once for every shape of shapes/shape_list.h: world rays
// are taken into object space by the inverse of Entity::worldFromObject
// without renormalising the direction, so t is the same parameter in both
// spaces, the shape's own code (shapes/*.cpp) tests and fills the hit, and
// the hit is taken back to world space. std::visit on Entity::shape is the
// one dispatch; no allocation: both backends call this per ray.
#include "geometry/shape.h"

#include "math/transform.h"
#include "geometry/csg_ray.h"
#include "geometry/csg_tree.h"
#include "math/error_bound.h"
#include "geometry/shapes/sphere_lanes.h"

#include <bit>

namespace lray {

namespace {

// Inlined into every shape's instantiation: as a call of its own, its
// result went through memory in pieces wider than they were written (a
// store-forwarding stall per shape test).
[[gnu::always_inline]] inline Ray objectRay(const Mat4 &inv, const Ray &worldRay) {
  return {affinePoint(inv, worldRay.o), affineVector(inv, worldRay.d), worldRay.tMin,
          worldRay.tMax, worldRay.time};
}

/// `worldRay` in the object space of `entity` where it is at the ray's time.
/// (Not one conditional expression: that would copy a static entity's
/// inverse matrix on every test.)
[[gnu::always_inline]] inline Ray objectRayAt(const Entity &entity, const Ray &worldRay) {
  if (!entity.motion) [[likely]]
    return objectRay(entity.worldFromObject.inverseMatrix(), worldRay);
  return objectRay(entity.motion->inverseMatrixAt(worldRay.time), worldRay);
}

// A distant origin makes the shapes' coefficients cancel: such rays are
// re-origined by the shape's originShift before its test, and the returned
// t is relative to that point.
// In place: a copy of the object ray, read in other pieces than it was
// written in, stalled every shape test on store forwarding.
[[gnu::always_inline]] inline void reorigin(Ray &ray, double by) {
  if (by == 0) return;
  ray.o = ray.at(by);
  ray.tMin -= by;
  ray.tMax -= by;
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
// matrix that defines the shape), then the shape's refine (Newton steps on
// its implicit function, or the exact solution for flat parts). Only below
// this cosine: unrefined, the far quadrics of tests/stress miss t by at
// most 1.74 / cos ulps (its "err*cos"), so up to 7 at 0.25, inside the
// suite's 8. The refinement is slow x87 arithmetic, and it runs on a
// sphere's rim, c^2 of its disc below cosine c: a sixteenth at 0.25, a
// quarter at 0.5, where the edge lattice's points crowd (bench/README.md,
// "Throughput").
constexpr double kRefineBelowCosine = 0.25;

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
template <class S>
double refineHitT(const S &shape, const Transform &xf, const Ray &worldRay, double shift, double t,
                  int part) {
  WideVec o = wideObjectSpace(xf, worldRay.o, true);
  WideVec d = wideObjectSpace(xf, worldRay.d, false);
  // Re-origin at the same point as the double test, for conditioning.
  const Wide sh = shift;
  o = {o.x + sh * d.x, o.y + sh * d.y, o.z + sh * d.z};
  std::optional<Wide> s = shape.refine(WideRay{o, d}, Wide(t) - sh, sh, part);
  if (!s) return t;
  double refined = static_cast<double>(*s + sh);
  return std::isfinite(refined) ? refined : t;
}

/// The surface at an object-space hit, without (u, v) where the shape can
/// leave them out and `uv` is false.
template <class S>
ObjectSurface surfaceOf(const S &shape, const Ray &ray, const ObjectHit &oh, bool uv) {
  if constexpr (requires { shape.surface(ray, oh, uv); })
    return shape.surface(ray, oh, uv);
  else
    return shape.surface(ray, oh);
}

/// A shape's test settled before its origin shift, where the shape can
/// (Sphere::missesLine): the same answer, false, as the full test.
template <class S>
[[gnu::always_inline]] inline bool clearlyMissed(const S &shape, const Ray &objectRay) {
  if constexpr (requires { shape.missesLine(objectRay); })
    return shape.missesLine(objectRay);
  else
    return false;
}

/// The hit of an object-space test's result `oh` on `ray` (the shifted
/// object ray of `worldRay`, re-origined by `shift`), before `tMax`; its
/// (u, v) as Entity::readsUv says (`uv`). `hit` is written only when it
/// returns true (a caller's best hit so far may be passed), and at the
/// end, field by field: a hit stored in pieces and then copied whole went
/// through a store-forwarding stall.
template <class S>
bool fillAnalytic(const S &shape, const Transform &xf, uint32_t entityIndex, const Ray &worldRay,
                  double tMax, bool uv, const Ray &ray, double shift, const ObjectHit &oh,
                  Hit &hit) {
  const ObjectSurface s = surfaceOf(shape, ray, oh, uv);
  double t = oh.t + shift;
  const Vec3 p = affinePoint(xf.matrix(), s.p);
  const Vec3 ng = unitVector(affineNormal(xf.inverseMatrix(), s.n));
  if (std::fabs(dot(ng, worldRay.d)) < kRefineBelowCosine * length(worldRay.d)) {
    const double refined = refineHitT(shape, xf, worldRay, shift, t, oh.part);
    // The refined t decides against tMax (exclusive), so a query bounded by
    // an earlier refined hit of this shape (a backend visiting it twice)
    // does not accept the same point again with its unrefined t. Below
    // tMin the double t stands: the ray may start on the surface.
    if (!(refined < tMax)) return false;
    if (refined > worldRay.tMin) t = refined;
  }
  hit.t = t;
  hit.time = worldRay.time;
  hit.entity = entityIndex;
  hit.primitive = 0;
  hit.pObject = s.p;
  hit.p = p;
  hit.ng = ng;
  hit.ns = ng;
  hit.u = s.u;
  hit.v = s.v;
  hit.pError = hitPointError(xf, s.p, p, 1.0, kDoubleRoundoff, kAnalyticErrorFactor);
  return true;
}

/// The shape's test with the ray taken into object space by `inverse`;
/// `placement()` gives the whole transform (whose inverse that is) only
/// for a hit: a moving entity's is computed then, not for every miss.
template <class S, class Placement>
bool intersectAnalytic(const S &shape, const Mat4 &inverse, Placement placement,
                       const Entity &entity, uint32_t entityIndex, const Ray &worldRay,
                       double tMax, Hit &hit) {
  Ray ray = objectRay(inverse, worldRay);
  ray.tMax = tMax;
  if (clearlyMissed(shape, ray)) return false;
  const double shift = shape.originShift(ray);
  reorigin(ray, shift);
  ObjectHit oh;
  if (!shape.intersect(ray, oh)) return false;
  return fillAnalytic(shape, placement(), entityIndex, worldRay, tMax, entity.readsUv, ray, shift,
                      oh, hit);
}

/// Any hit of the shape before `tMax`, the ray taken into object space by
/// `inverse`.
template <class S>
[[gnu::always_inline]] inline bool occludedAnalytic(const S &shape, const Mat4 &inverse,
                                                    const Ray &worldRay, double tMax) {
  Ray ray = objectRay(inverse, worldRay);
  ray.tMax = tMax;
  if (clearlyMissed(shape, ray)) return false;
  reorigin(ray, shape.originShift(ray));
  ObjectHit oh;
  return shape.intersect(ray, oh);
}

/// `worldRay` with the bound `tMax`, for the CSG code, which reads it off
/// the ray.
Ray bounded(const Ray &worldRay, double tMax) {
  Ray ray = worldRay;
  ray.tMax = tMax;
  return ray;
}

} // namespace

const char *shapeName(const Shape &shape) {
  if (const Csg *csg = std::get_if<Csg>(&shape))
    return csg->tree ? csgOpName(csg->tree->rootOp()) : Csg::kName;
  return std::visit([](const auto &s) { return std::decay_t<decltype(s)>::kName; }, shape);
}

bool shapeBounded(const Entity &entity) {
  return std::visit(
      [](const auto &s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Csg>) {
          if (!s.tree) return true;
          const Bounds3 &b = s.tree->bounds;
          return b.empty() || (std::isfinite(b.lo.x) && std::isfinite(b.lo.y) &&
                               std::isfinite(b.lo.z) && std::isfinite(b.hi.x) &&
                               std::isfinite(b.hi.y) && std::isfinite(b.hi.z));
        } else if constexpr (kAnalyticShape<S>) {
          return S::kBounded;
        } else {
          return true;
        }
      },
      entity.shape);
}

Bounds3 shapeWorldBounds(const Entity &entity, double t0, double t1) {
  return std::visit(
      [&](const auto &s) {
        using S = std::decay_t<decltype(s)>;
        // Meshes: meshObjectBounds + the backend's instance transform.
        if constexpr (std::is_same_v<S, Csg>) {
          // Over the whole shutter when its leaves move (their bounds are).
          return s.tree ? s.tree->bounds : Bounds3();
        } else if constexpr (kAnalyticShape<S>) {
          if (!entity.motion) return padded(s.worldBounds(entity.worldFromObject.matrix()));
          if constexpr (S::kBounded) {
            const Bounds3 objectBox = s.worldBounds(Mat4::identity());
            return entity.motion->sweptBounds(objectBox, t0, t1, [&](const Transform &xf) {
              return padded(s.worldBounds(xf.matrix()));
            });
          }
          return padded(s.worldBounds(entity.worldFromObject.matrix())); // infinite anyway
        } else {
          return Bounds3();
        }
      },
      entity.shape);
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

Ray objectSpaceRay(const Entity &entity, const Ray &worldRay) {
  return objectRayAt(entity, worldRay);
}

Bounds3 meshWorldBounds(const Entity &entity, double t0, double t1) {
  if (!entity.mesh) return {};
  const Bounds3 objectBox =
      entity.vertexMotion ? entity.vertexMotion->bounds() : meshObjectBounds(*entity.mesh);
  return entity.motion ? entity.motion->sweptBounds(objectBox, t0, t1)
                       : transformedBounds(objectBox, entity.worldFromObject);
}

Bounds3 stepWorldBounds(const Entity &entity, size_t step) {
  if (entity.isMesh()) {
    if (!entity.mesh) return {};
    if (!entity.motion) // only its vertices move (in straight lines)
      return transformedBounds(meshObjectBounds(*entity.vertexMotion->steps[step]),
                               entity.worldFromObject);
    const Bounds3 objectBox =
        entity.vertexMotion ? entity.vertexMotion->bounds() : meshObjectBounds(*entity.mesh);
    return entity.motion->stepBounds(objectBox, step, [&](const Transform &xf) {
      return transformedBounds(objectBox, xf);
    });
  }
  return std::visit(
      [&](const auto &s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kAnalyticShape<S> && !std::is_same_v<S, Csg>) {
          if constexpr (S::kBounded) {
            if (entity.motion)
              return entity.motion->stepBounds(s.worldBounds(Mat4::identity()), step,
                                               [&](const Transform &xf) {
                                                 return padded(s.worldBounds(xf.matrix()));
                                               });
          }
        }
        return shapeWorldBounds(entity); // a CSG's: over the whole shutter
      },
      entity.shape);
}

bool intersectShape(const Entity &entity, uint32_t entityIndex, const Ray &worldRay, double tMax,
                    Hit &hit) {
  return std::visit(
      [&](const auto &s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Csg>) {
          return intersectCsg(s, entityIndex, bounded(worldRay, tMax), hit);
        } else if constexpr (kAnalyticShape<S>) {
          if (!entity.motion) [[likely]]
            return intersectAnalytic(
                s, entity.worldFromObject.inverseMatrix(),
                [&]() -> const Transform & { return entity.worldFromObject; }, entity,
                entityIndex, worldRay, tMax, hit);
          // Moving: where it is at the ray's time.
          return intersectAnalytic(
              s, entity.motion->inverseMatrixAt(worldRay.time),
              [&] { return entity.motion->at(worldRay.time); }, entity, entityIndex, worldRay,
              tMax, hit);
        } else {
          return false;
        }
      },
      entity.shape);
}

bool occludedShape(const Entity &entity, const Ray &worldRay, double tMax) {
  return std::visit(
      [&](const auto &s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Csg>) {
          return occludedCsg(s, bounded(worldRay, tMax));
        } else if constexpr (kAnalyticShape<S>) {
          if (!entity.motion) [[likely]]
            return occludedAnalytic(s, entity.worldFromObject.inverseMatrix(), worldRay, tMax);
          return occludedAnalytic(s, entity.motion->inverseMatrixAt(worldRay.time), worldRay,
                                  tMax);
        } else {
          return false;
        }
      },
      entity.shape);
}

bool occludedStillSphere(const Entity &entity, const Ray &worldRay, double tMax) {
  return occludedAnalytic(*std::get_if<Sphere>(&entity.shape),
                          entity.worldFromObject.inverseMatrix(), worldRay, tMax);
}

namespace {

/// intersectAnalytic's steps for a still sphere, lane by lane
/// (sphere_lanes.h), up to the hit's t: the object rays, re-origined by
/// `shift`, in `r`; bit k of the result set where lane k hits before
/// tMax[k], its t in t[k]. Where Sphere::missesLine (clearlyMissed)
/// settles every lane's line, none hits, as in the full test: a shaft's
/// shadow rays past a sphere end there.
[[gnu::always_inline]] inline uint32_t sphereLanes(const Entity &entity,
                                                   const Ray *const (&rays)[4],
                                                   lanes::RayLanes &w,
                                                   const double (&tMax)[4], lanes::RayLanes &r,
                                                   lanes::Lanes &shift, lanes::Lanes &t) {
  const auto &m = entity.worldFromObject.inverseMatrix().m;
  lanes::loadRays(rays, w);
  // objectRay: affinePoint and affineVector.
  r.ox = m[0][0] * w.ox + m[0][1] * w.oy + m[0][2] * w.oz + m[0][3];
  r.oy = m[1][0] * w.ox + m[1][1] * w.oy + m[1][2] * w.oz + m[1][3];
  r.oz = m[2][0] * w.ox + m[2][1] * w.oy + m[2][2] * w.oz + m[2][3];
  r.dx = m[0][0] * w.dx + m[0][1] * w.dy + m[0][2] * w.dz;
  r.dy = m[1][0] * w.dx + m[1][1] * w.dy + m[1][2] * w.dz;
  r.dz = m[2][0] * w.dx + m[2][1] * w.dy + m[2][2] * w.dz;
  if (sphere_lanes::missesLines(r) == 0xF) return 0;
  r.tMin = w.tMin;
  lanes::load(tMax, r.tMax);
  shift = sphere_lanes::originShift(r, kFarOrigin);
  sphere_lanes::reorigin(r, shift);
  return sphere_lanes::intersect(r, t);
}

} // namespace

uint32_t intersectStillSphereLanes(const Entity &entity, uint32_t entityIndex,
                                   const Ray *const (&rays)[4], const double (&tMax)[4],
                                   uint32_t open, Hit *const (&hits)[4]) {
  // The hit's t in lanes, then fillAnalytic's steps for the four lanes in
  // lanes too, each operation the scalar code's in its order (the same
  // bits): Sphere::surface, the world point, the unit normal, the grazing
  // test and the error bound. A grazing lane (refined in long double) or
  // one at the centre takes fillAnalytic itself.
  const Sphere &sphere = *std::get_if<Sphere>(&entity.shape);
  using lanes::Lanes;
  using lanes::Mask;
  lanes::RayLanes w, r;
  Lanes shift, t;
  const uint32_t hitting = sphereLanes(entity, rays, w, tMax, r, shift, t) & open;
  if (hitting == 0) return 0;
  // Sphere::surface: o + d t snapped onto the sphere.
  const Lanes px = r.ox + r.dx * t, py = r.oy + r.dy * t, pz = r.oz + r.dz * t;
  Lanes len = px * px + py * py + pz * pz;
  lanes::sqrtInPlace(len);
  const Lanes sx = px / len, sy = py / len, sz = pz / len;
  // affinePoint and unitVector(affineNormal).
  const auto &m = entity.worldFromObject.matrix().m;
  const auto &inv = entity.worldFromObject.inverseMatrix().m;
  const Lanes wx = m[0][0] * sx + m[0][1] * sy + m[0][2] * sz + m[0][3];
  const Lanes wy = m[1][0] * sx + m[1][1] * sy + m[1][2] * sz + m[1][3];
  const Lanes wz = m[2][0] * sx + m[2][1] * sy + m[2][2] * sz + m[2][3];
  const Lanes nx = inv[0][0] * sx + inv[1][0] * sy + inv[2][0] * sz;
  const Lanes ny = inv[0][1] * sx + inv[1][1] * sy + inv[2][1] * sz;
  const Lanes nz = inv[0][2] * sx + inv[1][2] * sy + inv[2][2] * sz;
  Lanes nLen = nx * nx + ny * ny + nz * nz;
  lanes::sqrtInPlace(nLen);
  const Lanes unit = 1 / nLen;
  const Lanes gx = nx * unit, gy = ny * unit, gz = nz * unit;
  // The grazing test: |ng . d| < kRefineBelowCosine |d|.
  Lanes cosine = gx * w.dx + gy * w.dy + gz * w.dz, dLen = w.dx * w.dx + w.dy * w.dy + w.dz * w.dz;
  lanes::clearSigns(cosine);
  lanes::sqrtInPlace(dLen);
  const Mask scalar = (cosine < kRefineBelowCosine * dLen) | !(len > 0);
  // hitPointError's magnitudes.
  Lanes objectMagnitude, worldMagnitude;
  lanes::maxAbsComponent(sx, sy, sz, objectMagnitude);
  lanes::maxAbsComponent(wx, wy, wz, worldMagnitude);
  const Transform &xf = entity.worldFromObject;
  const double ke = kAnalyticErrorFactor * kDoubleRoundoff;
  const Lanes eObject = ke * (objectMagnitude + 1.0 + xf.inverseLinearNorm() * worldMagnitude +
                              xf.inverseTranslationNorm());
  const Lanes pError = eObject * xf.linearNorm() + ke * (worldMagnitude + xf.translationNorm());
  const Lanes hitT = t + shift;
  uint32_t found = 0;
  for (uint32_t left = hitting; left != 0; left &= left - 1) {
    const int k = std::countr_zero(left);
    if (scalar[k]) {
      const Ray ray{{r.ox[k], r.oy[k], r.oz[k]}, {r.dx[k], r.dy[k], r.dz[k]}, r.tMin[k],
                    r.tMax[k], rays[k]->time};
      // Into the caller's hit directly: fillAnalytic leaves it alone on a miss.
      if (fillAnalytic(sphere, xf, entityIndex, *rays[k], tMax[k], entity.readsUv, ray,
                       shift[k], ObjectHit{t[k], 0}, *hits[k]))
        found |= 1u << k;
      continue;
    }
    Hit &hit = *hits[k];
    hit.t = hitT[k];
    hit.time = rays[k]->time;
    hit.entity = entityIndex;
    hit.primitive = 0;
    hit.pObject = {sx[k], sy[k], sz[k]};
    hit.p = {wx[k], wy[k], wz[k]};
    hit.ng = {gx[k], gy[k], gz[k]};
    hit.ns = hit.ng;
    if (entity.readsUv) {
      hit.u = sphereU(sx[k], sz[k]);
      hit.v = sphereV(sy[k]);
    } else {
      hit.u = hit.v = 0;
    }
    hit.pError = pError[k];
    found |= 1u << k;
  }
  return found;
}

uint32_t occludedStillSphereLanes(const Entity &entity, const Ray *const (&rays)[4],
                                  const double (&tMax)[4]) {
  lanes::RayLanes w, r;
  lanes::Lanes shift, t;
  return sphereLanes(entity, rays, w, tMax, r, shift, t);
}

int shapeSpans(const Entity &entity, const Ray &worldRay, Span *out, double &shift) {
  return std::visit(
      [&](const auto &s) {
        if constexpr (kPrimitiveShape<std::decay_t<decltype(s)>>) {
          Ray ray = objectRayAt(entity, worldRay); // a moving leaf where it is then
          shift = s.originShift(ray);
          reorigin(ray, shift);
          return s.spans(ray, out);
        } else {
          shift = 0;
          return 0;
        }
      },
      entity.shape);
}

bool fillShapeHit(const Entity &entity, uint32_t entityIndex, const Ray &worldRay, double tObject,
                  int part, Hit &hit) {
  return std::visit(
      [&](const auto &s) {
        if constexpr (kPrimitiveShape<std::decay_t<decltype(s)>>) {
          auto fill = [&](const Transform &xf) {
            Ray ray = objectRay(xf.inverseMatrix(), worldRay);
            const double shift = s.originShift(ray);
            reorigin(ray, shift);
            return fillAnalytic(s, xf, entityIndex, worldRay, worldRay.tMax, entity.readsUv, ray,
                                shift, ObjectHit{tObject, part}, hit);
          };
          if (!entity.motion) return fill(entity.worldFromObject);
          return fill(entity.motion->at(worldRay.time)); // a moving leaf where it is then
        } else {
          return false;
        }
      },
      entity.shape);
}

} // namespace lray
