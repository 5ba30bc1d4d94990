// Pipeline: geometry. Mesh triangles after a backend's ray-triangle test:
// the hit record from the triangle index and barycentrics (shape.h).
// The point comes from the barycentric interpolation of the vertices, not
// from o + t d, so it lies on the triangle's plane up to a few ulps whatever
// the precision of the test that found it (pbrt's technique).
#include "geometry/affine.h"
#include "geometry/error_bound.h"
#include "geometry/shape.h"

#include <algorithm>

namespace lray {

namespace {

Vec3 toVec3(const Vec3f &v) { return {v.x, v.y, v.z}; }

/// Bound on how far the triangle and a ray leaving p can be misplaced by a
/// backend that works in single precision relative to `frameOrigin`
/// (float_frame.h): vertices rounded relative to it (an untransformed mesh)
/// or rays moved into object space through the float instance transform
/// Translate(-frameOrigin) * worldFromObject. With the frame at the world
/// origin this is the plain float bound of hitPointError.
double floatFrameError(const Transform &xf, const Vec3 &pObject, const Vec3 &p, double scale,
                       const Vec3 &frameOrigin, const Vec3 &p0, const Vec3 &p1,
                       const Vec3 &p2) {
  const double k = kTriangleErrorFactor * kFloatRoundoff;
  const Vec3 pRel = p - frameOrigin;
  if (xf.isIdentity()) {
    // The backend's vertices are float(v - origin), its ray origins
    // float(o - origin).
    double relScale =
        std::max(maxAbsComponent(p0 - frameOrigin),
                 std::max(maxAbsComponent(p1 - frameOrigin), maxAbsComponent(p2 - frameOrigin)));
    return k * (relScale + 3 * maxAbsComponent(pRel));
  }
  // hitPointError's terms for Translate(-origin) * worldFromObject: the
  // translation becomes t - origin, the inverse's becomes inverse(origin).
  const auto &m = xf.matrix().m;
  const auto &inv = xf.inverseMatrix().m;
  double rowNorm = 0, invNorm = 0;
  for (int i = 0; i < 3; ++i) {
    rowNorm = std::max(rowNorm, std::fabs(m[i][0]) + std::fabs(m[i][1]) + std::fabs(m[i][2]));
    invNorm = std::max(invNorm, std::fabs(inv[i][0]) + std::fabs(inv[i][1]) + std::fabs(inv[i][2]));
  }
  Vec3 t(m[0][3], m[1][3], m[2][3]);
  double tM = maxAbsComponent(t - frameOrigin);
  double tInv = maxAbsComponent(affinePoint(xf.inverseMatrix(), frameOrigin));
  double pw = maxAbsComponent(pRel);
  double eObject = k * (maxAbsComponent(pObject) + scale + invNorm * pw + tInv);
  return eObject * rowNorm + k * (pw + tM);
}

} // namespace

Bounds3 meshObjectBounds(const MeshData &mesh) {
  Bounds3 b;
  for (const Vec3f &p : mesh.positions) b.extend(toVec3(p));
  return b;
}

void fillTriangleHit(const Entity &entity, uint32_t entityIndex, uint32_t triangle, double t,
                     double b1, double b2, const Ray &worldRay, const Vec3 &frameOrigin,
                     Hit &hit) {
  const MeshData &mesh = *entity.mesh;
  const MeshTriangle &tri = mesh.triangles[triangle];
  const Transform &xf = entity.worldFromObject;
  Vec3 p0 = toVec3(mesh.positions[tri.v[0]]), p1 = toVec3(mesh.positions[tri.v[1]]),
       p2 = toVec3(mesh.positions[tri.v[2]]);
  // The backends' tests differ in precision (Embree's float barycentrics
  // are off by ~1e-7 of the triangle's size: on the 200-unit gallery floor
  // a checker edge moved by 1e-5), so the barycentrics and t are solved
  // again here in double, the same way for both: the backends then agree
  // on every hit of the same triangle, and points are as accurate as double
  // allows. Kept from the backend only when the double solve degenerates
  // (a ray in the triangle's plane) or leaves the query's interval.
  {
    Ray r = worldRay;
    if (!xf.isIdentity()) {
      r.o = affinePoint(xf.inverseMatrix(), worldRay.o);
      r.d = affineVector(xf.inverseMatrix(), worldRay.d);
    }
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    Vec3 pv = cross(r.d, e2);
    double det = dot(e1, pv);
    if (det != 0) {
      double inv = 1 / det;
      Vec3 tv = r.o - p0;
      Vec3 qv = cross(tv, e1);
      double u = dot(tv, pv) * inv, v = dot(r.d, qv) * inv, tt = dot(e2, qv) * inv;
      if (std::isfinite(u) && std::isfinite(v) && tt > worldRay.tMin && tt < worldRay.tMax) {
        b1 = u;
        b2 = v;
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

  hit.t = t;
  hit.entity = entityIndex;
  hit.primitive = triangle;
  hit.pObject = p0 * b0 + p1 * b1 + p2 * b2;
  hit.p = affinePoint(xf.matrix(), hit.pObject);

  // Face normal by the right-hand rule on the corner order (the scene
  // layer's computed vertex normals use the same convention).
  const Mat4 &inv = xf.inverseMatrix();
  Vec3 ng = affineNormal(inv, cross(p1 - p0, p2 - p0));
  double ngLen = length(ng);
  ng = ngLen > 0 ? ng * (1 / ngLen) : unitVector(-worldRay.d);

  // Vertex normals: by normal index, else per vertex index, else none.
  Vec3 nInterp;
  bool haveNormals = false;
  if (tri.n[0] >= 0 && tri.n[1] >= 0 && tri.n[2] >= 0) {
    nInterp = toVec3(mesh.normals[tri.n[0]]) * b0 + toVec3(mesh.normals[tri.n[1]]) * b1 +
              toVec3(mesh.normals[tri.n[2]]) * b2;
    haveNormals = true;
  } else if (mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty()) {
    nInterp = toVec3(mesh.normals[tri.v[0]]) * b0 + toVec3(mesh.normals[tri.v[1]]) * b1 +
              toVec3(mesh.normals[tri.v[2]]) * b2;
    haveNormals = true;
  }
  Vec3 ns = ng;
  if (haveNormals) {
    Vec3 n = affineNormal(inv, nInterp);
    double nLen = length(n);
    if (nLen > 0 && std::isfinite(nLen)) {
      n = n * (1 / nLen);
      // The mesh's normals say which side is outside; the face normal
      // follows them so that ng and ns are on the same side.
      if (dot(n, ng) < 0) ng = -ng;
      if (entity.smooth) ns = n;
    }
  }
  hit.ng = ng;
  hit.ns = entity.smooth ? ns : ng;

  if (tri.uv[0] >= 0 && tri.uv[1] >= 0 && tri.uv[2] >= 0) {
    const Vec2f &t0 = mesh.uvs[tri.uv[0]], &t1 = mesh.uvs[tri.uv[1]], &t2 = mesh.uvs[tri.uv[2]];
    hit.u = b0 * t0.u + b1 * t1.u + b2 * t2.u;
    hit.v = b0 * t0.v + b1 * t1.v + b2 * t2.v;
  } else {
    // Default mapping (SPEC 5): corners (0,0), (1,0), (0,1).
    hit.u = b1;
    hit.v = b2;
  }

  double scale = std::max(maxAbsComponent(p0), std::max(maxAbsComponent(p1), maxAbsComponent(p2)));
  hit.pError = std::max(floatFrameError(xf, hit.pObject, hit.p, scale, frameOrigin, p0, p1, p2),
                        hitPointError(xf, hit.pObject, hit.p, scale, kDoubleRoundoff,
                                      kAnalyticErrorFactor));
}

} // namespace lray
