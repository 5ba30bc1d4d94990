// Pipeline: geometry. fillTriangleHit (triangle_hit.cpp) for a batch of
// mesh hits, several at a time in SIMD lanes: a packet's fills are
// independent, and one at a time they are bound by the latency of the
// double re-solve and of the normalisations. Every lane performs the same
// IEEE operations in the same order as fillTriangleHit (no contraction:
// the baseline target has no FMA and the AVX2 variant does not enable it),
// so the hits are the same bit for bit (tests/geometry/triangle_hit_test).
#include "math/error_bound.h"
#include "math/lanes.h"
#include "geometry/shape.h"
#include "util/cpu_features.h"

namespace lray {

namespace {

// The four-double lanes of math/lanes.h (gather() below spells out the
// four). They are passed differently by the baseline and AVX ABIs: every
// function here taking one is inlined, so no call crosses (-Wno-psabi for
// this file, src/geometry/sources.cmake).
constexpr int kLanes = lanes::kWidth;
using lanes::Lanes;
using lanes::Mask;

struct Lanes3 {
  Lanes x, y, z;
};

// Lane-wise forms of vec3.h and error_bound.h, same operation order.
[[gnu::always_inline]] inline Lanes3 operator+(const Lanes3 &a, const Lanes3 &b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
[[gnu::always_inline]] inline Lanes3 operator-(const Lanes3 &a, const Lanes3 &b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[gnu::always_inline]] inline Lanes3 operator*(const Lanes3 &a, Lanes s) {
  return {a.x * s, a.y * s, a.z * s};
}
[[gnu::always_inline]] inline Lanes dot(const Lanes3 &a, const Lanes3 &b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[gnu::always_inline]] inline Lanes3 cross(const Lanes3 &a, const Lanes3 &b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[gnu::always_inline]] inline Lanes select(Mask m, Lanes a, Lanes b) { return m ? a : b; }
[[gnu::always_inline]] inline Lanes3 select(Mask m, const Lanes3 &a, const Lanes3 &b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
/// std::max(a, b) = a < b ? b : a.
[[gnu::always_inline]] inline Lanes maxLanes(Lanes a, Lanes b) { return a < b ? b : a; }
[[gnu::always_inline]] inline Lanes maxAbsComponent(const Lanes3 &v) {
  Lanes out;
  lanes::maxAbsComponent(v.x, v.y, v.z, out);
  return out;
}
/// std::sqrt lane-wise (lanes::sqrtInPlace).
[[gnu::always_inline]] inline Lanes sqrtLanes(Lanes v) {
  lanes::sqrtInPlace(v);
  return v;
}
/// std::isfinite: x - x is 0 exactly for finite x, NaN otherwise.
[[gnu::always_inline]] inline Mask finite(Lanes v) { return v - v == Lanes{}; }

/// A lane's corners, read as fillTriangleHit reads them.
struct LaneCorners {
  const Vec3f *p[3];
  const Vec3f *n[3]; ///< a zero vector for a mesh without normals (nw = 0: no normal)
  const int32_t *uv; ///< null: default mapping
};

const Vec3f kNoNormal{0, 0, 0};

[[gnu::always_inline]] inline LaneCorners laneCorners(const TriangleHitQuery &q) {
  const MeshData &mesh = *q.entity->mesh;
  LaneCorners c{};
  if (mesh.vertexNormalBase >= 0) {
    // Vertex-indexed normals: every corner has one (normal index = vertex
    // index + base >= 0), so fillTriangleHit takes them by index.
    const uint32_t *corners = &mesh.triangleIndices[3 * size_t(q.triangle)];
    const Vec3f *normals = mesh.normals.data() + mesh.vertexNormalBase;
    for (int k = 0; k < 3; ++k) {
      c.p[k] = &mesh.positions[corners[k]];
      c.n[k] = &normals[corners[k]];
    }
    return c;
  }
  uint32_t v[3];
  int32_t n[3];
  const MeshTriangle &tri = mesh.triangles[q.triangle];
  for (int k = 0; k < 3; ++k) {
    v[k] = tri.v[k];
    n[k] = tri.n[k];
  }
  c.uv = tri.uv;
  const bool byIndex = n[0] >= 0 && n[1] >= 0 && n[2] >= 0;
  const bool perVertex = mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty();
  for (int k = 0; k < 3; ++k) {
    c.p[k] = &mesh.positions[v[k]];
    c.n[k] = byIndex ? &mesh.normals[n[k]] : perVertex ? &mesh.normals[v[k]] : &kNoNormal;
  }
  return c;
}

/// Up to kLanes queries of identity-placed meshes, frame at the world
/// origin: fillTriangleHit's identity path with frameOrigin = 0, lane-wise.
/// Unused lanes repeat lane 0 and are not stored. kOneTriangle: every lane
/// hit the same triangle of the same mesh (a floor's packet, most often),
/// whose corners, normals and uvs are then read once for all lanes: the
/// same values, so the same bits.
template <bool kOneTriangle>
[[gnu::always_inline]] inline void fillLanes(const TriangleHitQuery *const *queries, int count) {
  const TriangleHitQuery *q[kLanes];
  LaneCorners c[kLanes];
  for (int i = 0; i < kLanes; ++i) {
    q[i] = queries[i < count ? i : 0];
    if (!kOneTriangle || i == 0) c[i] = laneCorners(*q[i]);
  }
  auto gather = [&](auto field) {
    return Lanes{field(0), field(1), field(2), field(3)};
  };
  // Corner k's position (or vertex normal) in every lane.
  auto corner = [&](bool normal, int k) {
    if constexpr (kOneTriangle) {
      const Vec3f &v = *(normal ? c[0].n[k] : c[0].p[k]);
      const double x = v.x, y = v.y, z = v.z;
      return Lanes3{Lanes{x, x, x, x}, Lanes{y, y, y, y}, Lanes{z, z, z, z}};
    }
    auto at = [&](int i) { return normal ? c[i].n[k] : c[i].p[k]; };
    return Lanes3{gather([&](int i) { return double(at(i)->x); }),
                  gather([&](int i) { return double(at(i)->y); }),
                  gather([&](int i) { return double(at(i)->z); })};
  };
  const Lanes3 p0 = corner(false, 0), p1 = corner(false, 1), p2 = corner(false, 2);
  const Lanes3 o{gather([&](int i) { return q[i]->ray->o.x; }),
                 gather([&](int i) { return q[i]->ray->o.y; }),
                 gather([&](int i) { return q[i]->ray->o.z; })};
  const Lanes3 d{gather([&](int i) { return q[i]->ray->d.x; }),
                 gather([&](int i) { return q[i]->ray->d.y; }),
                 gather([&](int i) { return q[i]->ray->d.z; })};
  Lanes t = gather([&](int i) { return q[i]->t; });
  Lanes b1 = gather([&](int i) { return q[i]->b1; });
  Lanes b2 = gather([&](int i) { return q[i]->b2; });
  const Lanes zero{}, one = zero + 1;

  // The double re-solve, kept where the scalar code keeps it.
  Lanes3 e1 = p1 - p0, e2 = p2 - p0;
  Lanes3 pv = cross(d, e2);
  Lanes det = dot(e1, pv);
  Lanes inv = one / det;
  Lanes3 tv = o - p0;
  Lanes3 qv = cross(tv, e1);
  Lanes u = dot(tv, pv) * inv, w = dot(d, qv) * inv, tt = dot(e2, qv) * inv;
  Mask solved = (det != zero) & finite(u) & finite(w) &
                (tt > gather([&](int i) { return q[i]->ray->tMin; })) &
                (tt < gather([&](int i) { return q[i]->ray->tMax; }));
  b1 = select(solved, u, b1);
  b2 = select(solved, w, b2);
  t = select(solved, tt, t);
  // std::clamp(b, 0, 1), then back onto the triangle.
  b1 = b1 < zero ? zero : (one < b1 ? one : b1);
  b2 = b2 < zero ? zero : (one < b2 ? one : b2);
  Lanes s = b1 + b2;
  Mask outside = s > one;
  // The divisions (and below, the gathers and a square root) only where a
  // lane needs them: the lanes they leave alone keep their bits, and a
  // floor's hits, inside their triangles and without vertex normals, need
  // none of them.
  if (lanes::bits(outside) != 0) {
    b1 = select(outside, b1 / s, b1);
    b2 = select(outside, b2 / s, b2);
  }
  Lanes b0 = one - b1 - b2;

  Lanes3 pObject = p0 * b0 + p1 * b1 + p2 * b2;
  Lanes3 ng = cross(e1, e2);
  // A mesh without normals gives every lane the zero vector: nw is 0 (or
  // -0), no lane has a normal, and the gathers are left out.
  bool anyNormals = c[0].n[0] != &kNoNormal;
  if constexpr (!kOneTriangle)
    for (int i = 1; i < kLanes; ++i) anyNormals |= c[i].n[0] != &kNoNormal;
  Lanes3 nw{zero, zero, zero};
  if (anyNormals) nw = corner(true, 0) * b0 + corner(true, 1) * b1 + corner(true, 2) * b2;
  Lanes nwLen2 = dot(nw, nw);
  Mask haveNormal = (nwLen2 > zero) & finite(nwLen2);
  Mask flip = haveNormal & (dot(nw, ng) < zero);
  Lanes ngLen = sqrtLanes(dot(ng, ng));
  Lanes3 ngFace = ng * (select(flip, -one, one) / ngLen);
  Mask faceNormal = ngLen > zero;
  ng = ngFace;
  bool anyDegenerate = false;
  for (int i = 0; i < kLanes; ++i) anyDegenerate |= faceNormal[i] == 0;
  if (anyDegenerate) {
    // Degenerate triangle: facing the ray, on the normals' side.
    Lanes3 back{-d.x, -d.y, -d.z};
    back = back * (one / sqrtLanes(dot(back, back)));
    Mask backFlip = haveNormal & (dot(nw, back) < zero);
    back = select(backFlip, Lanes3{-back.x, -back.y, -back.z}, back);
    ng = select(faceNormal, ngFace, back);
  }
  Mask smooth = haveNormal & (gather([&](int i) { return q[i]->entity->smooth ? 1.0 : 0.0; }) != 0);
  Lanes3 ns = ng;
  if (lanes::bits(smooth) != 0) ns = select(smooth, nw * (one / sqrtLanes(nwLen2)), ng);

  // hitPointErrorFromMagnitudes with the float roundoff (frame at the origin).
  Lanes scale = maxLanes(maxAbsComponent(p0), maxLanes(maxAbsComponent(p1), maxAbsComponent(p2)));
  Lanes magnitude = maxAbsComponent(pObject);
  const double keps = kTriangleErrorFactor * kFloatRoundoff;
  // hitPointErrorFromNorms with an identity transform's norms (linear 1,
  // inverse linear 1, translations 0): x * 1 and y + 0 (y >= 0) are exact,
  // so dropping them keeps the bits.
  Lanes eObject = keps * (magnitude + scale + magnitude);
  Lanes pError = eObject + keps * magnitude;

  // The uvs: lane-wise from one triangle's corners (each lane's sums in
  // the scalar order below), else lane by lane.
  const int32_t *oneUv = c[0].uv;
  const bool uvLanes = kOneTriangle && oneUv && oneUv[0] >= 0 && oneUv[1] >= 0 && oneUv[2] >= 0;
  Lanes hu = b1, hv = b2;
  if (uvLanes) {
    const MeshData &mesh = *q[0]->entity->mesh;
    const Vec2f &t0 = mesh.uvs[oneUv[0]], &t1 = mesh.uvs[oneUv[1]], &t2 = mesh.uvs[oneUv[2]];
    hu = b0 * double(t0.u) + b1 * double(t1.u) + b2 * double(t2.u);
    hv = b0 * double(t0.v) + b1 * double(t1.v) + b2 * double(t2.v);
  }
  for (int i = 0; i < count; ++i) {
    Hit &hit = *q[i]->hit;
    hit.t = t[i];
    hit.time = q[i]->ray->time;
    hit.entity = q[i]->entityIndex;
    hit.primitive = q[i]->triangle;
    hit.pObject = {pObject.x[i], pObject.y[i], pObject.z[i]};
    hit.p = hit.pObject;
    hit.ng = {ng.x[i], ng.y[i], ng.z[i]};
    hit.ns = {ns.x[i], ns.y[i], ns.z[i]};
    const int32_t *uv = c[kOneTriangle ? 0 : i].uv;
    if (kOneTriangle || !(uv && uv[0] >= 0 && uv[1] >= 0 && uv[2] >= 0)) {
      hit.u = hu[i];
      hit.v = hv[i];
    } else {
      const MeshData &mesh = *q[i]->entity->mesh;
      const Vec2f &t0 = mesh.uvs[uv[0]], &t1 = mesh.uvs[uv[1]], &t2 = mesh.uvs[uv[2]];
      hit.u = b0[i] * t0.u + b1[i] * t1.u + b2[i] * t2.u;
      hit.v = b0[i] * t0.v + b1[i] * t1.v + b2[i] * t2.v;
    }
    hit.pError = pError[i];
  }
}

/// Whether the first `count` queries hit one triangle of one mesh.
bool oneTriangle(const TriangleHitQuery *const *queries, int count) {
  for (int i = 1; i < count; ++i)
    if (queries[i]->triangle != queries[0]->triangle || queries[i]->entity != queries[0]->entity)
      return false;
  return true;
}

/// fillLanes, reading the corners once where every query hit one triangle.
[[gnu::always_inline]] inline void fillLanesOf(const TriangleHitQuery *const *queries,
                                               int count) {
  if (oneTriangle(queries, count))
    fillLanes<true>(queries, count);
  else
    fillLanes<false>(queries, count);
}

void fillLanesBaseline(const TriangleHitQuery *const *queries, int count) {
  fillLanesOf(queries, count);
}

__attribute__((target("avx2"))) void fillLanesAvx2(const TriangleHitQuery *const *queries,
                                                   int count) {
  fillLanesOf(queries, count);
}

} // namespace

namespace detail {

void fillTriangleHits(const TriangleHitQuery *queries, size_t count, const Vec3 &frameOrigin,
                      bool avx2) {
  // Lanes take identity-placed meshes with the frame at the origin; the
  // rest (instances, far scenes) go through fillTriangleHit.
  const bool frameAtOrigin = frameOrigin == Vec3(0, 0, 0);
  const TriangleHitQuery *lanes[kLanes];
  int used = 0;
  auto flush = [&] {
    if (used == 0) return;
    if (avx2)
      fillLanesAvx2(lanes, used);
    else
      fillLanesBaseline(lanes, used);
    used = 0;
  };
  for (size_t i = 0; i < count; ++i) {
    const TriangleHitQuery &q = queries[i];
    if (frameAtOrigin && q.entity->worldFromObject.isIdentity() && !q.entity->moves()) {
      lanes[used++] = &q;
      if (used == kLanes) flush();
    } else {
      fillTriangleHit(*q.entity, q.entityIndex, q.triangle, q.t, q.b1, q.b2, *q.ray, frameOrigin,
                      *q.hit);
    }
  }
  flush();
}

} // namespace detail

void fillTriangleHits(const TriangleHitQuery *queries, size_t count, const Vec3 &frameOrigin) {
  detail::fillTriangleHits(queries, count, frameOrigin, cpuHasAvx2());
}

} // namespace lray
