// Pipeline: geometry. Mesh triangles after a backend's ray-triangle test:
// the hit record from the triangle index and barycentrics (shape.h).
// The point comes from the barycentric interpolation of the vertices, not
// from o + t d, so it lies on the triangle's plane up to a few ulps whatever
// the precision of the test that found it (pbrt's technique).
#include "math/transform.h"
#include "math/error_bound.h"
#include "geometry/shape.h"

#include <algorithm>

namespace lray {

namespace {

/// Bound on how far the triangle and a ray leaving p can be misplaced by a
/// backend that works in single precision relative to `frameOrigin`
/// (float_frame.h): vertices rounded relative to it (an untransformed mesh)
/// or rays moved into object space through the float instance transform
/// Translate(-frameOrigin) * worldFromObject. With the frame at the world
/// origin this is the plain float bound of hitPointError.
double floatFrameError(const Transform &xf, const Vec3 &pObject, const Vec3 &p, double scale,
                       const Vec3 &frameOrigin, const Vec3 &p0, const Vec3 &p1,
                       const Vec3 &p2) {
  const double pw = maxAbsComponent(p - frameOrigin);
  if (xf.isIdentity()) {
    // The backend's vertices are float(v - origin), its ray origins
    // float(o - origin): the rule for an identity transform in that frame.
    double relScale =
        std::max(maxAbsComponent(p0 - frameOrigin),
                 std::max(maxAbsComponent(p1 - frameOrigin), maxAbsComponent(p2 - frameOrigin)));
    return hitPointErrorFromNorms({1, 1, 0, 0}, pw, pw, relScale, kFloatRoundoff,
                                  kTriangleErrorFactor);
  }
  // The rule for Translate(-origin) * worldFromObject: the translation
  // becomes t - origin, the inverse's becomes inverse(origin).
  const auto &m = xf.matrix().m;
  TransformNorms n{xf.linearNorm(), xf.inverseLinearNorm(),
                   maxAbsComponent(Vec3(m[0][3], m[1][3], m[2][3]) - frameOrigin),
                   maxAbsComponent(affinePoint(xf.inverseMatrix(), frameOrigin))};
  return hitPointErrorFromNorms(n, maxAbsComponent(pObject), pw, scale, kFloatRoundoff,
                                kTriangleErrorFactor);
}

} // namespace

Bounds3 meshObjectBounds(const MeshData &mesh) {
  Bounds3 b;
  for (const Vec3f &p : mesh.positions) b.extend(toVec3(p));
  return b;
}

// triangle_hits.cpp repeats this arithmetic lane-wise for Embree's packets
// (identity-placed meshes, frame at the origin): a change here must be made
// there too, in the same operation order; the FillTriangleHits test compares
// the two bit for bit.
namespace {

/// A triangle's corners: vertex and normal indices, uv indices (or none),
/// and positions in object space at the ray's time.
struct Corners {
  uint32_t v[3];
  int32_t n[3];
  const int32_t *uv = nullptr;
  Vec3 p[3];
};

[[gnu::always_inline]] inline Corners cornersAt(const Entity &entity, uint32_t triangle,
                                                float time) {
  const MeshData &mesh = *entity.mesh;
  Corners c;
  // A hit is usually a cache miss on these: read the 12-byte
  // triangleIndices entry when the corners carry nothing more
  // (vertex-indexed normals, no uvs), else the 36-byte MeshTriangle.
  if (mesh.vertexNormalBase >= 0) {
    const uint32_t *corners = &mesh.triangleIndices[3 * size_t(triangle)];
    for (int k = 0; k < 3; ++k) {
      c.v[k] = corners[k];
      c.n[k] = static_cast<int32_t>(c.v[k]) + mesh.vertexNormalBase;
    }
  } else {
    const MeshTriangle &tri = mesh.triangles[triangle];
    for (int k = 0; k < 3; ++k) {
      c.v[k] = tri.v[k];
      c.n[k] = tri.n[k];
    }
    c.uv = tri.uv;
  }
  const MeshMotion *deform = entity.vertexMotion.get();
  for (int k = 0; k < 3; ++k) // moving vertices: where they are at the ray's time
    c.p[k] = deform ? deform->position(c.v[k], time) : toVec3(mesh.positions[c.v[k]]);
  return c;
}

/// Barycentrics a hair outside the triangle (a hit on an edge): keep the
/// point on it.
void clampBarycentrics(double &b1, double &b2) {
  b1 = std::clamp(b1, 0.0, 1.0);
  b2 = std::clamp(b2, 0.0, 1.0);
  if (b1 + b2 > 1) {
    double s = b1 + b2;
    b1 /= s;
    b2 /= s;
  }
}

/// The world point at barycentrics (b1, b2), clamped onto the triangle, of
/// object-space corners p placed by xf; b0 gets corner 0's weight.
Vec3 placedPoint(const Vec3 (&p)[3], const Transform &xf, double &b1, double &b2, double &b0) {
  clampBarycentrics(b1, b2);
  b0 = 1 - b1 - b2;
  const Vec3 pObject = p[0] * b0 + p[1] * b1 + p[2] * b2;
  return xf.isIdentity() ? pObject : affinePoint(xf.matrix(), pObject);
}

/// The unit geometric normal `ng` at barycentrics (b0, b1, b2) in world
/// space, and the interpolated vertex normal `nw` (world, not normalised;
/// nwLen2 = 0 when the mesh has none): ng is on the side the vertex normals
/// say is outside, and against `rayDir` where the triangle is degenerate.
struct TriangleNormals {
  Vec3 ng, nw;
  double nwLen2 = 0;
  bool vertexNormals = false; ///< whether the mesh gives this triangle's corners normals
  Vec3 face; ///< the face normal in world space before it is flipped or normalised
};

[[gnu::always_inline]] inline TriangleNormals
triangleNormals(const Entity &entity, const Corners &c, const Transform &xf, double b0, double b1,
                double b2, float time, const Vec3 &rayDir) {
  const MeshData &mesh = *entity.mesh;
  const bool identity = xf.isIdentity();
  // Face normal by the right-hand rule on the corner order (the scene
  // layer's computed vertex normals use the same convention).
  const Mat4 &inv = xf.inverseMatrix();
  TriangleNormals out;
  Vec3 ng = cross(c.p[1] - c.p[0], c.p[2] - c.p[0]);
  if (!identity) ng = affineNormal(inv, ng);
  out.face = ng;

  // Vertex normals: by normal index, else per vertex index, else none.
  int64_t normalAt[3] = {-1, -1, -1};
  if (c.n[0] >= 0 && c.n[1] >= 0 && c.n[2] >= 0) {
    for (int k = 0; k < 3; ++k)
      normalAt[k] = c.n[k];
  } else if (mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty()) {
    for (int k = 0; k < 3; ++k)
      normalAt[k] = c.v[k];
  }
  out.vertexNormals = normalAt[0] >= 0;
  if (out.vertexNormals) {
    const MeshMotion *deform = entity.vertexMotion.get();
    Vec3 cn[3];
    for (int k = 0; k < 3; ++k)
      cn[k] = deform ? deform->normal(static_cast<uint32_t>(normalAt[k]), time)
                     : toVec3(mesh.normals[static_cast<size_t>(normalAt[k])]);
    out.nw = cn[0] * b0 + cn[1] * b1 + cn[2] * b2;
    if (!identity) out.nw = affineNormal(inv, out.nw);
    out.nwLen2 = dot(out.nw, out.nw);
  }
  if (!(out.nwLen2 > 0 && std::isfinite(out.nwLen2))) out.nwLen2 = 0;
  const bool haveNormal = out.nwLen2 > 0;
  // The mesh's normals say which side is outside; the face normal follows
  // them so that ng and ns are on the same side (the sign needs no
  // normalisation, so it does not wait for the square roots).
  const bool flip = haveNormal && dot(out.nw, ng) < 0;
  double ngLen = length(ng);
  if (ngLen > 0) {
    ng *= (flip ? -1 : 1) / ngLen;
  } else {
    ng = unitVector(-rayDir);
    if (haveNormal && dot(out.nw, ng) < 0) ng = -ng;
  }
  out.ng = ng;
  return out;
}

/// fillTriangleHit with the entity placed by `xf` (its own transform, or a
/// moving one's at the ray's time).
void fillPlacedTriangleHit(const Entity &entity, const Transform &xf, uint32_t entityIndex,
                           uint32_t triangle, double t, double b1, double b2, const Ray &worldRay,
                           const Vec3 &frameOrigin, Hit &hit) {
  const Corners c = cornersAt(entity, triangle, worldRay.time);
  const Vec3 &p0 = c.p[0], &p1 = c.p[1], &p2 = c.p[2];
  // Most meshes are placed by their vertices: skip the products (an
  // identity product gives the same values).
  const bool identity = xf.isIdentity();
  // The backends' tests differ in precision (Embree's float barycentrics
  // are off by ~1e-7 of the triangle's size: on the 200-unit gallery floor
  // a checker edge moved by 1e-5), so the barycentrics and t are solved
  // again here in double, the same way for both: the backends then agree
  // on every hit of the same triangle, and points are as accurate as double
  // allows. Kept from the backend only when the double solve degenerates
  // (a ray in the triangle's plane) or leaves the query's interval.
  {
    Vec3 o = worldRay.o, d = worldRay.d;
    if (!identity) {
      o = affinePoint(xf.inverseMatrix(), worldRay.o);
      d = affineVector(xf.inverseMatrix(), worldRay.d);
    }
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    Vec3 pv = cross(d, e2);
    double det = dot(e1, pv);
    if (det != 0) {
      double inv = 1 / det;
      Vec3 tv = o - p0;
      Vec3 qv = cross(tv, e1);
      double u = dot(tv, pv) * inv, w = dot(d, qv) * inv, tt = dot(e2, qv) * inv;
      if (std::isfinite(u) && std::isfinite(w) && tt > worldRay.tMin && tt < worldRay.tMax) {
        b1 = u;
        b2 = w;
        t = tt;
      }
    }
  }
  clampBarycentrics(b1, b2);
  double b0 = 1 - b1 - b2;

  // Everything is computed in locals and stored once at the end: stores
  // into `hit` in between would make the compiler reload through it.
  Vec3 pObject = p0 * b0 + p1 * b1 + p2 * b2;
  Vec3 p = identity ? pObject : affinePoint(xf.matrix(), pObject);
  const TriangleNormals normals =
      triangleNormals(entity, c, xf, b0, b1, b2, worldRay.time, worldRay.d);
  Vec3 ns = normals.ng;
  if (normals.nwLen2 > 0 && entity.smooth) ns = normals.nw * (1 / std::sqrt(normals.nwLen2));

  hit.t = t;
  hit.time = worldRay.time;
  hit.entity = entityIndex;
  hit.primitive = triangle;
  hit.pObject = pObject;
  hit.p = p;
  hit.ng = normals.ng;
  hit.ns = ns;
  const MeshData &mesh = *entity.mesh;
  const int32_t *uv = c.uv;
  if (uv && uv[0] >= 0 && uv[1] >= 0 && uv[2] >= 0) {
    const Vec2f &t0 = mesh.uvs[uv[0]], &t1 = mesh.uvs[uv[1]], &t2 = mesh.uvs[uv[2]];
    hit.u = b0 * t0.u + b1 * t1.u + b2 * t2.u;
    hit.v = b0 * t0.v + b1 * t1.v + b2 * t2.v;
  } else {
    // Default mapping (lua/README.md, "Entities"): corners (0,0), (1,0), (0,1).
    hit.u = b1;
    hit.v = b2;
  }

  double scale = std::max(maxAbsComponent(p0), std::max(maxAbsComponent(p1), maxAbsComponent(p2)));
  double objectMagnitude = maxAbsComponent(pObject);
  double worldMagnitude = identity ? objectMagnitude : maxAbsComponent(p);
  if (frameOrigin == Vec3(0, 0, 0)) {
    // The float bound (which dominates the double one term by term).
    hit.pError = hitPointErrorFromMagnitudes(xf, objectMagnitude, worldMagnitude, scale,
                                             kFloatRoundoff, kTriangleErrorFactor);
  } else {
    hit.pError = std::max(floatFrameError(xf, pObject, p, scale, frameOrigin, p0, p1, p2),
                          hitPointErrorFromMagnitudes(xf, objectMagnitude, worldMagnitude, scale,
                                                      kDoubleRoundoff, kAnalyticErrorFactor));
  }
}

} // namespace

void fillTriangleHit(const Entity &entity, uint32_t entityIndex, uint32_t triangle, double t,
                     double b1, double b2, const Ray &worldRay, const Vec3 &frameOrigin, Hit &hit) {
  if (entity.motion) [[unlikely]] { // where it is at the ray's time
    const Transform moved = entity.motion->at(worldRay.time);
    fillPlacedTriangleHit(entity, moved, entityIndex, triangle, t, b1, b2, worldRay, frameOrigin,
                          hit);
    return;
  }
  fillPlacedTriangleHit(entity, entity.worldFromObject, entityIndex, triangle, t, b1, b2, worldRay,
                        frameOrigin, hit);
}

void triangleSurfacePoint(const Entity &entity, uint32_t triangle, double b1, double b2,
                          float time, Vec3 &p, Vec3 &ng) {
  const Transform placement = entity.placementAt(time);
  const Corners c = cornersAt(entity, triangle, time);
  double b0;
  p = placedPoint(c.p, placement, b1, b2, b0);
  ng = triangleNormals(entity, c, placement, b0, b1, b2, time, Vec3(0, 0, 1)).ng;
}

FixedTriangle::FixedTriangle(const Entity &entity, uint32_t triangle)
    : entity_(&entity), triangle_(triangle) {
  const Corners c = cornersAt(entity, triangle, 0);
  for (int k = 0; k < 3; ++k)
    corner_[k] = c.p[k];
  // The side of ng follows the sign of dot(nw, face), nw the interpolated
  // vertex normal and face the unflipped face normal (both in world space,
  // where the sign is taken): a weighted mean of the corners' dots. The
  // same sign at all three corners, well clear of 0, is that sign
  // everywhere on the triangle.
  const Transform &xf = entity.worldFromObject;
  int positive = 0, negative = 0, without = 0;
  for (int k = 0; k < 3; ++k) {
    const double b1 = k == 1 ? 1 : 0, b2 = k == 2 ? 1 : 0;
    const TriangleNormals at =
        triangleNormals(entity, c, xf, 1 - b1 - b2, b1, b2, 0, Vec3(0, 0, 1));
    const double faceLength = length(at.face);
    if (!(faceLength > 0) || !std::isfinite(faceLength)) return; // degenerate: none constant
    if (!at.vertexNormals) ++without;
    if (!(at.nwLen2 > 0)) continue;
    const double cosine = dot(at.nw, at.face) / (std::sqrt(at.nwLen2) * faceLength);
    positive += cosine > 1e-6;
    negative += cosine < -1e-6;
  }
  constantNormal_ = without == 3 || positive == 3 || negative == 3;
  if (constantNormal_)
    ng_ = triangleNormals(entity, c, xf, 1.0 / 3, 1.0 / 3, 1.0 / 3, 0, Vec3(0, 0, 1)).ng;
}

void FixedTriangle::surfacePoint(double b1, double b2, Vec3 &p, Vec3 &ng) const {
  if (!constantNormal_) {
    triangleSurfacePoint(*entity_, triangle_, b1, b2, 0, p, ng);
    return;
  }
  double b0;
  p = placedPoint(corner_, entity_->worldFromObject, b1, b2, b0);
  ng = ng_;
}

} // namespace lray
