// Tests for src/shading: a tiny brute-force accelerator for the integrator
// tests, independent of the real backends. Loops over every entity. Two
// modes: its own analytic unit sphere, unit cube and flat triangle tests in
// object space (an oracle independent of src/geometry), or the shared shape
// code of geometry/shape.h (intersectShape, and fillTriangleHit after its
// own triangle test) as the real backends use it.
#pragma once

#include "accel/accelerator.h"
#include "render/film.h"
#include "render/frame_settings.h"
#include "shading/image_cache.h"
#include "shading/ray_counts.h"
#include "math/hit.h"
#include "geometry/shape.h"
#include "math/ray.h"
#include "geometry/float_frame.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace lray::testing {

class BruteForceAccelerator final : public Accelerator {
public:
  /// sharedShapeCode: use geometry/shape.h instead of the local shape tests.
  explicit BruteForceAccelerator(const Scene &scene, bool sharedShapeCode = false)
      : scene_(scene), shared_(sharedShapeCode) {
    for (const Entity &e : scene.entities) objectFromWorld_.push_back(e.worldFromObject.inverse());
  }

  bool intersect(const Ray &ray, Hit &hit) const override {
    Ray r = ray;
    bool found = false;
    for (uint32_t i = 0; i < scene_.entities.size(); ++i) {
      if (intersectEntity(i, r, hit)) {
        r.tMax = hit.t;
        found = true;
      }
    }
    return found;
  }

  bool occluded(const Ray &ray) const override { return occludedBy(ray, nullptr); }

  void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const override {
    for (size_t i = 0; i < count; ++i) found[i] = intersect(rays[i], hits[i]) ? 1 : 0;
  }
  /// With the shared shape code, an analytic blocker is named as the real
  /// backends name it; the local tests name none.
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occ,
                        uint32_t *blockers) const override {
    for (size_t i = 0; i < count; ++i) {
      if (blockers) blockers[i] = kNoEntity;
      occ[i] = occludedBy(rays[i], blockers ? blockers + i : nullptr) ? 1 : 0;
    }
  }
  AcceleratorStats stats() const override { return {}; }

private:
  bool occludedBy(const Ray &ray, uint32_t *blocker) const {
    Hit hit;
    for (uint32_t i = 0; i < scene_.entities.size(); ++i) {
      const Entity &e = scene_.entities[i];
      if (shared_ && e.kind() != ShapeKind::Mesh) {
        if (!occludedShape(e, ray)) continue;
        if (blocker) *blocker = i;
        return true;
      }
      if (intersectEntity(i, ray, hit)) return true;
    }
    return false;
  }

  bool intersectEntity(uint32_t index, const Ray &worldRay, Hit &hit) const {
    const Entity &e = scene_.entities[index];
    Ray r = objectFromWorld_[index].applyRay(worldRay); // same t in both spaces
    double t = 0;
    Vec3 nObject;
    double u = 0, v = 0;
    uint32_t triangle = 0;
    bool ok = false;
    if (shared_ && e.kind() != ShapeKind::Mesh) return intersectShape(e, index, worldRay, hit);
    switch (e.kind()) {
    case ShapeKind::Sphere: ok = sphere(r, t, nObject, u, v); break;
    case ShapeKind::Cube: ok = cube(r, t, nObject); break;
    case ShapeKind::Mesh: ok = mesh(*e.mesh, r, t, nObject, u, v, triangle); break;
    default: break;
    }
    if (!ok) return false;
    if (shared_) {
      fillTriangleHit(e, index, triangle, t, u, v, worldRay, floatFrameOrigin(scene_), hit);
      return true;
    }
    hit.t = t;
    hit.entity = index;
    hit.primitive = 0;
    hit.pObject = r.at(t);
    hit.p = e.worldFromObject.applyPoint(hit.pObject);
    hit.ng = normalize(e.worldFromObject.applyNormal(nObject));
    hit.ns = hit.ng;
    hit.u = u;
    hit.v = v;
    double m = std::max({std::fabs(hit.p.x), std::fabs(hit.p.y), std::fabs(hit.p.z), 1.0});
    hit.pError = 1e-9 * m;
    return true;
  }

  static bool sphere(const Ray &r, double &t, Vec3 &n, double &u, double &v) {
    double a = dot(r.d, r.d), b = dot(r.o, r.d), c = dot(r.o, r.o) - 1;
    double disc = b * b - a * c;
    if (disc < 0) return false;
    double s = std::sqrt(disc);
    double t0 = (-b - s) / a, t1 = (-b + s) / a;
    if (t0 > r.tMin && t0 < r.tMax) t = t0;
    else if (t1 > r.tMin && t1 < r.tMax) t = t1;
    else return false;
    n = r.at(t);
    u = (std::atan2(n.z, n.x) + std::numbers::pi) / (2 * std::numbers::pi);
    v = (n.y + 1) / 2;
    return true;
  }

  static bool cube(const Ray &r, double &t, Vec3 &n) {
    double tNear = -1e300, tFar = 1e300;
    int nearAxis = 0, farAxis = 0;
    for (int a = 0; a < 3; ++a) {
      if (r.d[a] == 0) {
        if (std::fabs(r.o[a]) > 0.5) return false;
        continue;
      }
      double ta = (-0.5 - r.o[a]) / r.d[a], tb = (0.5 - r.o[a]) / r.d[a];
      if (ta > tb) std::swap(ta, tb);
      if (ta > tNear) { tNear = ta; nearAxis = a; }
      if (tb < tFar) { tFar = tb; farAxis = a; }
    }
    if (tNear > tFar) return false;
    int axis;
    if (tNear > r.tMin && tNear < r.tMax) { t = tNear; axis = nearAxis; }
    else if (tFar > r.tMin && tFar < r.tMax) { t = tFar; axis = farAxis; }
    else return false;
    n = Vec3();
    n[axis] = r.at(t)[axis] > 0 ? 1 : -1;
    return true;
  }

  static bool mesh(const MeshData &m, const Ray &r, double &t, Vec3 &n, double &u, double &v,
                   uint32_t &triangle) {
    bool found = false;
    double tMax = r.tMax;
    for (uint32_t k = 0; k < m.triangles.size(); ++k) {
      const MeshTriangle &tri = m.triangles[k];
      auto pos = [&](int corner) {
        const Vec3f &p = m.positions[tri.v[corner]];
        return Vec3(p.x, p.y, p.z);
      };
      Vec3 p0 = pos(0), e1 = pos(1) - p0, e2 = pos(2) - p0;
      Vec3 pv = cross(r.d, e2);
      double det = dot(e1, pv);
      if (det == 0) continue;
      Vec3 tv = r.o - p0;
      double b1 = dot(tv, pv) / det;
      if (b1 < 0 || b1 > 1) continue;
      Vec3 qv = cross(tv, e1);
      double b2 = dot(r.d, qv) / det;
      if (b2 < 0 || b1 + b2 > 1) continue;
      double tt = dot(e2, qv) / det;
      if (tt <= r.tMin || tt >= tMax) continue;
      t = tMax = tt;
      n = normalize(cross(e1, e2));
      u = b1;
      v = b2;
      triangle = k;
      found = true;
    }
    return found;
  }

  const Scene &scene_;
  bool shared_;
  std::vector<Transform> objectFromWorld_;
};

/// A frame through the same tile loop and integrator as the real backends
/// (brute_force_render.cpp); chosen over render/renderer.h's renderFrame for
/// this accelerator, which no backend of render/backends.h built.
Film renderFrame(const Scene &scene, const BruteForceAccelerator &accel, const ImageCache &images,
                 const FrameSettings &settings, RayCounts &counts,
                 const ProgressFn &progress = nullptr);

} // namespace lray::testing
