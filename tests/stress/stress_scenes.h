// Test helpers for tests/stress (the robustness suite, issue 8): the small
// stress scene placed at any offset and scale, the backend parameter, a
// brute-force closest-entity reference and image comparison.
#pragma once

#include "accel/accel_test_scenes.h"
#include "render/backends.h"
#include "geometry/shape.h"
#include "render/camera_rays.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "shading/image_cache.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace lray::stress {

/// Both backends, for INSTANTIATE_TEST_SUITE_P.
inline const BackendKind kBothBackends[] = {BackendKind::Embree, BackendKind::KdTree};

inline std::string backendParamName(const ::testing::TestParamInfo<BackendKind> &info) {
  return backendName(info.param);
}

// Scene-building helpers shared with the backend tests.
using lray::testing::makeMesh;
using lray::testing::meshEntity;
using lray::testing::shapeEntity;

/// One default texture and a white pigment, as the scene layer provides.
inline void addDefaultMaterials(Scene &s) {
  s.textures = {Texture{}};
  s.pigments = {Pigment{}};
}

/// The stress scene of the scale and offset sweeps. Built in a "unit frame"
/// (a 40 x 40 floor at y = 0, objects of size ~1 a few units apart, a point
/// light up and to the left) and then moved to the world by
/// `world` = Translate(offset, offset, offset) * Scale(scale): all
/// entities, the light and the camera go through `world`, so every view of
/// the scene is the same picture.
struct StressScene {
  Scene scene;
  Transform world;
  Transform unitFromWorld;
  Vec3 lightUnit;
  Vec3 lightWorld;
  /// Unit-frame bounds of each entity (for the analytic "is anything in
  /// between" test).
  std::vector<Bounds3> unitBounds;
  double scale = 1;
  static constexpr uint32_t kFloor = 0;
  static constexpr uint32_t kSphere = 1;
};

/// Optional occluders: thin plates 1e-3 (unit frame, i.e. 1e-3 x scale in
/// the world) above the floor and above the top of the sphere.
struct Plates {
  static constexpr double kGap = 1e-3;
  static constexpr double kThickness = 1e-4;
  // Centres (unit frame, x and z) of the plates.
  static constexpr double kFloorCubeX = -8,
                          kFloorCubeZ = 12; ///< analytic cube plate over the floor
  static constexpr double kFloorMeshX = 8, kFloorMeshZ = 12;   ///< triangle plate over the floor
  static constexpr double kSphereX = -2.5, kSphereZ = 6;       ///< cube plate over the sphere's top
  static constexpr double kSphereTop = 2.5;
};

inline StressScene makeStressScene(double offset, double scale, bool withPlates = false) {
  StressScene st;
  st.scale = scale;
  st.world = Transform::translate({offset, offset, offset}) * Transform::scale(scale, scale, scale);
  st.unitFromWorld = st.world.inverse();
  Scene &s = st.scene;
  std::vector<Entity> unit; // entities in the unit frame

  // Floor: its vertices are baked into world space (floats, identity
  // transform: Embree attaches it directly), as a large OBJ would be.
  {
    std::vector<Vec3f> p;
    for (Vec3 c : {Vec3(-20, 0, -10), Vec3(20, 0, -10), Vec3(20, 0, 30), Vec3(-20, 0, 30)}) {
      Vec3 w = st.world.applyPoint(c);
      p.push_back({float(w.x), float(w.y), float(w.z)});
    }
    Entity floor = meshEntity(makeMesh(p, {0, 2, 1, 0, 3, 2}), Transform());
    s.entities.push_back(floor);
    unit.push_back(meshEntity(makeMesh({{-20, 0, -10}, {20, 0, -10}, {20, 0, 30}, {-20, 0, 30}},
                                       {0, 2, 1, 0, 3, 2}),
                              Transform()));
  }
  unit.push_back(shapeEntity(ShapeKind::Sphere, Transform::translate({-2.5, 1.5, 6})));
  unit.push_back(shapeEntity(ShapeKind::Cube, Transform::translate({0, 1.2, 7}) *
                                                  Transform::rotate({0, 1, 0}, 30) *
                                                  Transform::scale(1.5, 1.5, 1.5)));
  unit.push_back(shapeEntity(ShapeKind::Cylinder,
                             Transform::translate({2.5, 0.3, 6}) * Transform::scale(0.8, 2, 0.8)));
  unit.push_back(shapeEntity(ShapeKind::Cone, Transform::translate({1, 0.3, 3.5}) *
                                                  Transform::scale(0.7, 1.5, 0.7)));
  // A closed pyramid mesh, placed by its transform (an Embree instance).
  auto pyramid = makeMesh({{-0.6f, 0, -0.6f}, {0.6f, 0, -0.6f}, {0.6f, 0, 0.6f}, {-0.6f, 0, 0.6f},
                           {0, 1.2f, 0}},
                          {0, 1, 2, 0, 2, 3, 0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0});
  unit.push_back(meshEntity(pyramid, Transform::translate({-1.5, 0.2, 2.5}) *
                                         Transform::rotate({0, 1, 0}, 20)));
  // A torus lying on the floor (not convex, but lit from above at ~50
  // degrees its lit side cannot shadow itself).
  unit.push_back(shapeEntity(ShapeKind::Torus, Transform::translate({3, 0.25, 1.5})));
  if (withPlates) {
    const double h = Plates::kGap + Plates::kThickness / 2;
    unit.push_back(shapeEntity(ShapeKind::Cube,
                               Transform::translate({Plates::kFloorCubeX, h, Plates::kFloorCubeZ}) *
                                   Transform::scale(1, Plates::kThickness, 1)));
    unit.push_back(shapeEntity(
        ShapeKind::Cube,
        Transform::translate({Plates::kSphereX, Plates::kSphereTop + h, Plates::kSphereZ}) *
            Transform::scale(0.2, Plates::kThickness, 0.2)));
    // Triangle plate: a unit square at y = 0, moved up by its transform.
    auto quad = makeMesh({{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}},
                         {0, 2, 1, 0, 3, 2});
    unit.push_back(meshEntity(
        quad, Transform::translate({Plates::kFloorMeshX, Plates::kGap, Plates::kFloorMeshZ})));
  }
  for (size_t i = 0; i < unit.size(); ++i) {
    const Entity &e = unit[i];
    Bounds3 b;
    if (e.kind() == ShapeKind::Mesh) {
      for (const Vec3f &p : e.mesh->positions) b.extend(e.worldFromObject.applyPoint(toVec3(p)));
    } else {
      b = shapeWorldBounds(e);
    }
    st.unitBounds.push_back(b);
    if (i == 0) continue; // the floor is already in world space
    Entity w = e;
    w.worldFromObject = st.world * e.worldFromObject;
    s.entities.push_back(w);
  }
  st.lightUnit = {-6, 14, -2};
  st.lightWorld = st.world.applyPoint(st.lightUnit);
  Light light;
  light.worldFromLight = st.world * Transform::translate(st.lightUnit);
  s.lights.push_back(light);
  s.camera.fov = 50;
  s.camera.aspect = 4.0 / 3.0;
  s.camera.worldFromCamera = st.world * Transform::lookAt({0, 4, -6}, {0, 0.8, 6}, {0, 1, 0});
  s.background = {0.1, 0.1, 0.3};
  addDefaultMaterials(s);
  return st;
}

/// Segment a -> b meets the box (slab test, closed).
inline bool segmentHitsBox(const Vec3 &a, const Vec3 &b, const Bounds3 &box) {
  double t0 = 0, t1 = 1;
  Vec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (a[i] < box.lo[i] || a[i] > box.hi[i]) return false;
      continue;
    }
    double ta = (box.lo[i] - a[i]) / d[i], tb = (box.hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

/// Primary rays of the scene's camera, one per pixel centre.
inline std::vector<Ray> cameraRays(const Scene &s, int width, int height) {
  CameraRays cam(s.camera, width, height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) rays.push_back(cam.generate(x + 0.5, y + 0.5));
  return rays;
}

/// Closest hit's entity through a backend's coherent query; -1 = miss.
inline std::vector<int> hitEntities(const Accelerator &accel, const std::vector<Ray> &rays,
                                    std::vector<Hit> *hitsOut = nullptr) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> found(rays.size());
  accel.intersectCoherent(rays.data(), rays.size(), hits.data(), found.data());
  std::vector<int> ids(rays.size());
  for (size_t i = 0; i < rays.size(); ++i)
    ids[i] = found[i] ? static_cast<int>(hits[i].entity) : -1;
  if (hitsOut) *hitsOut = std::move(hits);
  return ids;
}

/// Every field of a hit record is finite and the normals are unit.
inline bool hitIsFinite(const Hit &h) {
  auto fin = [](const Vec3 &v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  return std::isfinite(h.t) && fin(h.p) && fin(h.pObject) && fin(h.ng) && fin(h.ns) &&
         std::isfinite(h.u) && std::isfinite(h.v) && std::isfinite(h.pError) &&
         std::fabs(length(h.ng) - 1) < 1e-6 && std::fabs(length(h.ns) - 1) < 1e-6;
}

/// Renders with renderFrame and asserts that no sample was non-finite.
inline Film renderChecked(const Scene &scene, BackendKind kind, int width, int height,
                          int samples = 1) {
  auto accel = makeAccelerator(kind, scene);
  ImageCache images(false);
  FrameSettings fs;
  fs.width = width;
  fs.height = height;
  fs.samples = samples;
  RayCounts counts;
  Film film = renderFrame(scene, *accel, images, fs, counts);
  EXPECT_EQ(counts.nonFinite, 0u) << "non-finite samples reached the film";
  return film;
}

/// Image difference: fraction of pixels whose largest channel difference
/// exceeds `tol`, and the mean absolute difference.
struct ImageDiff {
  double fractionOver = 0;
  double meanAbs = 0;
};

inline ImageDiff compareFilms(const Film &a, const Film &b, double tol) {
  ImageDiff d;
  size_t over = 0, n = static_cast<size_t>(a.width()) * a.height();
  double sum = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      Color ca = a.get(x, y), cb = b.get(x, y);
      double m = std::max({std::fabs(ca.r - cb.r), std::fabs(ca.g - cb.g), std::fabs(ca.b - cb.b)});
      sum += m;
      if (m > tol) ++over;
    }
  d.fractionOver = static_cast<double>(over) / static_cast<double>(n);
  d.meanAbs = sum / static_cast<double>(n);
  return d;
}

} // namespace lray::stress
