// Test helpers for tests/accel: hand-built scenes (entities, MeshData) and
// an independent brute-force reference (double precision) to compare the
// backends against.
#pragma once

#include "geometry/shape.h"
#include "scene/scene.h"

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace lray::testing {

/// MeshData from positions and flat indices (no uvs, no normals).
inline std::shared_ptr<MeshData> makeMesh(std::vector<Vec3f> positions,
                                          const std::vector<uint32_t> &indices) {
  auto m = std::make_shared<MeshData>();
  m->positions = std::move(positions);
  m->triangleIndices = indices;
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    MeshTriangle t;
    for (int j = 0; j < 3; ++j) t.v[j] = indices[i + j];
    m->triangles.push_back(t);
  }
  return m;
}

/// A closed icosphere of about unit radius, 20 * 4^subdivisions triangles,
/// each vertex's radius jittered by up to +-`jitter` (vertices shared, so
/// the mesh stays closed), wound so cross(p1 - p0, p2 - p0) points out.
inline std::shared_ptr<MeshData> makeJitteredSphere(int subdivisions, double jitter,
                                                    uint64_t seed) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1,  0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (Vec3 &p : v) p = normalize(p);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalize(v[a] + v[b]));
      auto idx = static_cast<uint32_t>(v.size() - 1);
      mid[key] = idx;
      return idx;
    };
    std::vector<uint32_t> nf;
    for (size_t i = 0; i < f.size(); i += 3) {
      uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      for (uint32_t x : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) nf.push_back(x);
    }
    f = std::move(nf);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<Vec3f> pos;
  for (const Vec3 &p : v) {
    Vec3 q = p * (1 + u(rng));
    pos.push_back({float(q.x), float(q.y), float(q.z)});
  }
  return makeMesh(std::move(pos), f);
}

inline Entity shapeEntity(ShapeKind kind, const Transform &xf) {
  Entity e;
  e.shape = makeShape(kind);
  e.worldFromObject = xf;
  return e;
}

inline Entity meshEntity(MeshDataPtr mesh, const Transform &xf) {
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = std::move(mesh);
  e.worldFromObject = xf;
  return e;
}

/// Double-precision Moller-Trumbore on the object-space ray `r` (the world
/// ray through the inverse of the entity transform; t in world units).
inline bool referenceTriangle(const Entity &e, uint32_t tri, const Ray &r, double &t) {
  const MeshData &m = *e.mesh;
  auto P = [&](int j) {
    const Vec3f &p = m.positions[m.triangles[tri].v[j]];
    return Vec3(p.x, p.y, p.z);
  };
  Vec3 p0 = P(0), e1 = P(1) - p0, e2 = P(2) - p0;
  Vec3 pv = cross(r.d, e2);
  double det = dot(e1, pv);
  if (det == 0) return false;
  Vec3 tv = r.o - p0;
  double b1 = dot(tv, pv) / det;
  if (b1 < 0 || b1 > 1) return false;
  Vec3 qv = cross(tv, e1);
  double b2 = dot(r.d, qv) / det;
  if (b2 < 0 || b1 + b2 > 1) return false;
  t = dot(e2, qv) / det;
  return t > r.tMin && t < r.tMax;
}

/// Brute force over all entities: closest (entity, t), entity = -1 if none.
inline std::pair<int, double> bruteForce(const Scene &scene, const Ray &ray) {
  int best = -1;
  double bestT = ray.tMax;
  for (size_t i = 0; i < scene.entities.size(); ++i) {
    const Entity &e = scene.entities[i];
    Ray r = ray;
    r.tMax = bestT;
    if (e.kind() == ShapeKind::Mesh) {
      Ray objectRay = Transform::fromMatrix(e.worldFromObject.inverseMatrix()).applyRay(r);
      for (uint32_t k = 0; k < e.mesh->triangles.size(); ++k) {
        double t;
        if (referenceTriangle(e, k, objectRay, t) && t < bestT) {
          bestT = t;
          objectRay.tMax = t;
          best = static_cast<int>(i);
        }
      }
    } else {
      Hit h;
      if (intersectShape(e, static_cast<uint32_t>(i), r, h)) {
        bestT = h.t;
        best = static_cast<int>(i);
      }
    }
  }
  return {best, bestT};
}

} // namespace lray::testing
