// Tests for src/accel/kdtree: deterministic random numbers, a closed jittered
// sphere mesh and brute-force references for the kd-tree tests.
#pragma once

#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/triangle_clip.h"
#include "accel/kdtree/watertight_triangle.h"
#include "math/bounds.h"
#include "math/ray.h"
#include "scene/mesh_data.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

namespace lray::kdtest {

/// SplitMix64: the same numbers on every platform.
class Rng {
public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t nextBits() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(nextBits() >> 11) * 0x1p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  Vec3 inBox(const Vec3 &lo, const Vec3 &hi) {
    return {uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)};
  }
  Vec3 direction() {
    for (;;) {
      Vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
      double l2 = dot(v, v);
      if (l2 > 1e-6 && l2 <= 1) return v / std::sqrt(l2);
    }
  }

private:
  uint64_t state_;
};

/// Triangles as three float-exact corners each (as meshes store them).
struct TriangleSoup {
  std::vector<Vec3> corners; ///< 3 per triangle

  size_t size() const { return corners.size() / 3; }
  static Vec3 roundToFloat(const Vec3 &v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
  }
  void add(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    corners.push_back(roundToFloat(a));
    corners.push_back(roundToFloat(b));
    corners.push_back(roundToFloat(c));
  }
  std::vector<Bounds3> bounds() const {
    std::vector<Bounds3> out;
    for (size_t i = 0; i < size(); ++i) {
      Bounds3 b(corners[3 * i], corners[3 * i + 1]);
      b.extend(corners[3 * i + 2]);
      out.push_back(b);
    }
    return out;
  }
  KdClipFunction clipper() const {
    return [this](uint32_t i, const Bounds3 &box) {
      return clipTriangleToBox(corners[3 * i], corners[3 * i + 1], corners[3 * i + 2], box);
    };
  }
  KdTree buildTree(const KdBuildOptions &options = {}) const {
    std::vector<Bounds3> b = bounds();
    return KdTree::build(b, clipper(), options);
  }
};

/// Closest triangle hit: t and triangle index (~0u when none).
struct Nearest {
  double t = 0;
  uint32_t prim = ~0u;
  bool found() const { return prim != ~0u; }
};

inline Nearest bruteForce(const TriangleSoup &soup, const Ray &ray) {
  WatertightRay wr(ray);
  Nearest best;
  double tMax = ray.tMax;
  TriangleHitParams p;
  for (uint32_t i = 0; i < soup.size(); ++i) {
    if (intersectTriangle(wr, soup.corners[3 * i], soup.corners[3 * i + 1], soup.corners[3 * i + 2],
                          tMax, p)) {
      tMax = p.t;
      best = {p.t, i};
    }
  }
  return best;
}

template <KdRays Rays = KdRays::Incoherent>
Nearest treeNearest(const KdTree &tree, const TriangleSoup &soup, const Ray &ray) {
  WatertightRay wr(ray);
  Nearest best;
  double tMax = ray.tMax;
  tree.traverse<false, Rays>(ray, tMax, [&](uint32_t i, double &tBest) {
    TriangleHitParams p;
    const Vec3 *c = &soup.corners[3 * size_t{i}];
    if (!intersectTriangle(wr, c[0], c[1], c[2], tBest, p))
      return false;
    tBest = p.t;
    best = {p.t, i};
    return true;
  });
  return best;
}

template <KdRays Rays = KdRays::Incoherent>
bool treeOccluded(const KdTree &tree, const TriangleSoup &soup, const Ray &ray) {
  WatertightRay wr(ray);
  double tMax = ray.tMax;
  return tree.traverse<true, Rays>(ray, tMax, [&](uint32_t i, double &tBest) {
    TriangleHitParams p;
    return intersectTriangle(wr, soup.corners[3 * i], soup.corners[3 * i + 1],
                             soup.corners[3 * i + 2], tBest, p);
  });
}

/// A closed latitude/longitude sphere (poles as single vertices, consistent
/// winding) with every vertex's radius jittered by up to `jitter`.
inline MeshDataPtr makeJitteredSphere(int rings, int segments, double jitter, uint64_t seed) {
  auto mesh = std::make_shared<MeshData>();
  Rng rng(seed);
  auto addVertex = [&](double theta, double phi) {
    double r = 1 + jitter * rng.uniform(-1, 1);
    Vec3 p = Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                  std::sin(theta) * std::sin(phi)) * r;
    mesh->positions.push_back(toVec3f(p));
    mesh->normals.push_back(toVec3f(normalize(p)));
  };
  addVertex(0, 0); // north pole
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
      addVertex(std::numbers::pi * i / rings, 2 * std::numbers::pi * j / segments);
  addVertex(std::numbers::pi, 0); // south pole
  const uint32_t south = static_cast<uint32_t>(mesh->positions.size() - 1);
  auto ring = [&](int i, int j) {
    return static_cast<uint32_t>(1 + (i - 1) * segments + (j % segments));
  };
  auto addTriangle = [&](uint32_t a, uint32_t b, uint32_t c) {
    MeshTriangle t;
    t.v[0] = a;
    t.v[1] = b;
    t.v[2] = c;
    for (int k = 0; k < 3; ++k) t.n[k] = static_cast<int32_t>(t.v[k]);
    mesh->triangles.push_back(t);
    mesh->triangleIndices.insert(mesh->triangleIndices.end(), {a, b, c});
  };
  for (int j = 0; j < segments; ++j) addTriangle(0, ring(1, j + 1), ring(1, j));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      addTriangle(ring(i, j), ring(i, j + 1), ring(i + 1, j));
      addTriangle(ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j));
    }
  for (int j = 0; j < segments; ++j) addTriangle(south, ring(rings - 1, j), ring(rings - 1, j + 1));
  mesh->hasNormals = true;
  return mesh;
}

inline TriangleSoup soupFromMesh(const MeshData &mesh) {
  TriangleSoup soup;
  for (uint32_t idx : mesh.triangleIndices) soup.corners.push_back(toVec3(mesh.positions[idx]));
  return soup;
}

} // namespace lray::kdtest
