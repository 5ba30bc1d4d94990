// Robustness suite (issue 8): the kd-tree and Embree agree on the entity
// hit by at least 99.99 % of the primary rays of every stress scene.
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace lray::stress {
namespace {

/// Fraction of `rays` on which the two backends name a different entity.
double disagreement(const Scene &scene, const std::vector<Ray> &rays, size_t &differing) {
  auto embree = makeAccelerator(BackendKind::Embree, scene);
  auto kdtree = makeAccelerator(BackendKind::KdTree, scene);
  std::vector<int> a = hitEntities(*embree, rays), b = hitEntities(*kdtree, rays);
  differing = 0;
  for (size_t i = 0; i < rays.size(); ++i) differing += a[i] != b[i];
  return static_cast<double>(differing) / static_cast<double>(rays.size());
}

TEST(StressBackendParity, SweepScenesAgreeOnHitEntity) {
  const double offsets[] = {0, 1e2, 1e3, 1e4, 1e5};
  const double scales[] = {1e-4, 1e-3, 1e-2, 1e-1, 1e1, 1e2, 1e3, 1e4};
  std::vector<std::pair<double, double>> cases;
  for (double o : offsets) cases.push_back({o, 1});
  for (double s : scales) cases.push_back({0, s});
  for (auto [offset, scale] : cases) {
    for (bool plates : {false, true}) {
      StressScene st = makeStressScene(offset, scale, plates);
      std::vector<Ray> rays = cameraRays(st.scene, 200, 150);
      size_t differing;
      double f = disagreement(st.scene, rays, differing);
      std::printf("[parity] offset %-6g scale %-6g plates %d: %zu of %zu primary rays differ "
                  "(%.2e)\n",
                  offset, scale, plates, differing, rays.size(), f);
      EXPECT_LE(f, 1e-4) << "offset " << offset << " scale " << scale;
    }
  }
}

TEST(StressBackendParity, GridAndDegenerateScenesAgreeOnHitEntity) {
  // Grid of touching boxes and spheres at split-plane coordinates, a
  // floor, and a mesh of thin and zero-area triangles, seen through a
  // camera whose pixel rays include axis-parallel ones.
  Scene s;
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 8; ++k) {
      bool cube = (i + k) % 2 == 0;
      s.entities.push_back(shapeEntity(
          cube ? ShapeKind::Cube : (k % 3 == 0 ? ShapeKind::Cylinder : ShapeKind::Sphere),
          Transform::translate({i - 3.5, 0.5, double(k)}) *
              (cube ? Transform::scale(1, 1, 1) : Transform::scale(0.5, 0.5, 0.5))));
    }
  std::vector<Vec3f> pos;
  std::vector<uint32_t> idx;
  for (int i = 0; i < 200; ++i) {
    float x = -4 + 0.04f * i;
    auto b = static_cast<uint32_t>(pos.size());
    pos.push_back({x, 1.2f, 3});
    pos.push_back({x + 0.04f, 1.2f, 3});
    pos.push_back({x + 0.02f, 1.2f + 1e-6f * float(i % 3), 3}); // slivers and zero-area
    idx.insert(idx.end(), {b, b + 1, b + 2});
  }
  s.entities.push_back(meshEntity(makeMesh(pos, idx), Transform()));
  s.entities.push_back(meshEntity(makeMesh({{-20, 0, -5}, {20, 0, -5}, {20, 0, 30}, {-20, 0, 30}},
                                           {0, 2, 1, 0, 3, 2}),
                                  Transform()));
  addDefaultMaterials(s);
  s.camera.aspect = 4.0 / 3;
  s.camera.worldFromCamera = Transform::lookAt({0, 0.5, -6}, {0, 0.5, 4}, {0, 1, 0});
  std::vector<Ray> rays = cameraRays(s, 256, 192);
  size_t differing;
  double f = disagreement(s, rays, differing);
  std::printf("[parity] grid + slivers: %zu of %zu primary rays differ (%.2e)\n", differing,
              rays.size(), f);
  EXPECT_LE(f, 1e-4);
}

} // namespace
} // namespace lray::stress
