// Pipeline: geometry. Mesh triangles after a backend's ray-triangle test:
// the hit record from the triangle index and barycentrics (shape.h).
// The point comes from the barycentric interpolation of the vertices, not
// from o + t d, so it lies on the triangle's plane up to a few ulps whatever
// the precision of the test that found it (pbrt's technique).
#include "math/affine.h"
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

/// fillTriangleHit with the entity placed by `xf` (its own transform, or a
/// moving one's at the ray's time).
void fillPlacedTriangleHit(const Entity &entity, const Transform &xf, uint32_t entityIndex,
                           uint32_t triangle, double t, double b1, double b2, const Ray &worldRay,
                           const Vec3 &frameOrigin, Hit &hit) {
  const MeshData &mesh = *entity.mesh;
  // Corner indices. A hit is usually a cache miss on these: read the
  // 12-byte triangleIndices entry when the corners carry nothing more
  // (vertex-indexed normals, no uvs), else the 36-byte MeshTriangle.
  uint32_t v[3];
  int32_t n[3];
  const int32_t *uv = nullptr;
  if (mesh.vertexNormalBase >= 0) {
    const uint32_t *corners = &mesh.triangleIndices[3 * size_t(triangle)];
    for (int k = 0; k < 3; ++k) {
      v[k] = corners[k];
      n[k] = static_cast<int32_t>(v[k]) + mesh.vertexNormalBase;
    }
  } else {
    const MeshTriangle &tri = mesh.triangles[triangle];
    for (int k = 0; k < 3; ++k) {
      v[k] = tri.v[k];
      n[k] = tri.n[k];
    }
    uv = tri.uv;
  }
  // Most meshes are placed by their vertices: skip the products (an
  // identity product gives the same values).
  const bool identity = xf.isIdentity();
  Vec3 p0 = toVec3(mesh.positions[v[0]]), p1 = toVec3(mesh.positions[v[1]]),
       p2 = toVec3(mesh.positions[v[2]]);
  const MeshMotion *deform = entity.vertexMotion.get();
  if (deform) { // moving vertices: where they are at the ray's time
    p0 = deform->position(v[0], worldRay.time);
    p1 = deform->position(v[1], worldRay.time);
    p2 = deform->position(v[2], worldRay.time);
  }
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
  // Barycentrics a hair outside the triangle (a hit on an edge): keep the
  // point on it.
  b1 = std::clamp(b1, 0.0, 1.0);
  b2 = std::clamp(b2, 0.0, 1.0);
  if (b1 + b2 > 1) {
    double s = b1 + b2;
    b1 /= s;
    b2 /= s;
  }
  double b0 = 1 - b1 - b2;

  // Everything is computed in locals and stored once at the end: stores
  // into `hit` in between would make the compiler reload through it.
  Vec3 pObject = p0 * b0 + p1 * b1 + p2 * b2;
  Vec3 p = identity ? pObject : affinePoint(xf.matrix(), pObject);

  // Face normal by the right-hand rule on the corner order (the scene
  // layer's computed vertex normals use the same convention).
  const Mat4 &inv = xf.inverseMatrix();
  Vec3 ng = cross(p1 - p0, p2 - p0);
  if (!identity) ng = affineNormal(inv, ng);

  // Vertex normals: by normal index, else per vertex index, else none.
  int64_t normalAt[3] = {-1, -1, -1};
  if (n[0] >= 0 && n[1] >= 0 && n[2] >= 0) {
    for (int k = 0; k < 3; ++k)
      normalAt[k] = n[k];
  } else if (mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty()) {
    for (int k = 0; k < 3; ++k)
      normalAt[k] = v[k];
  }
  Vec3 nw;
  double nwLen2 = 0;
  if (normalAt[0] >= 0) {
    Vec3 c[3];
    for (int k = 0; k < 3; ++k)
      c[k] = deform ? deform->normal(static_cast<uint32_t>(normalAt[k]), worldRay.time)
                    : toVec3(mesh.normals[static_cast<size_t>(normalAt[k])]);
    nw = c[0] * b0 + c[1] * b1 + c[2] * b2;
    if (!identity) nw = affineNormal(inv, nw);
    nwLen2 = dot(nw, nw);
  }
  bool haveNormal = nwLen2 > 0 && std::isfinite(nwLen2);
  // The mesh's normals say which side is outside; the face normal follows
  // them so that ng and ns are on the same side (the sign needs no
  // normalisation, so it does not wait for the square roots).
  bool flip = haveNormal && dot(nw, ng) < 0;

  double ngLen = length(ng);
  if (ngLen > 0) {
    ng *= (flip ? -1 : 1) / ngLen;
  } else {
    ng = unitVector(-worldRay.d);
    if (haveNormal && dot(nw, ng) < 0) ng = -ng;
  }
  Vec3 ns = ng;
  if (haveNormal && entity.smooth) ns = nw * (1 / std::sqrt(nwLen2));

  hit.t = t;
  hit.time = worldRay.time;
  hit.entity = entityIndex;
  hit.primitive = triangle;
  hit.pObject = pObject;
  hit.p = p;
  hit.ng = ng;
  hit.ns = ns;
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

} // namespace lray
