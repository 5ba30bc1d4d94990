// Test helper for the render tests: a small scene of silhouettes and
// smooth shading on a flat background, and a fixture rendering it.
#pragma once

#include "render/backends.h"
#include "render/render_films.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <memory>

namespace lray::test {

/// A bright disc (a sphere lit from the camera) on a dark background, and
/// a smaller one behind it: silhouettes and shading, no area light.
inline Scene silhouetteScene() {
  Scene s;
  Pigment p;
  p.pattern = ColorPigment{Color(0.9, 0.8, 0.3)};
  s.pigments.push_back(p);
  Finish f;
  f.specular = 0.3;
  f.exponent = 10;
  s.textures.push_back({f, 0});
  for (int k = 0; k < 2; ++k) {
    Entity e;
    e.shape = Sphere{};
    e.worldFromObject = k == 0 ? Transform::translate({-0.4, 0.1, 0})
                               : Transform::translate({0.9, -0.3, 2}) *
                                     Transform::scale(0.7, 0.7, 0.7);
    e.texture = 0;
    s.entities.push_back(e);
  }
  Light light;
  light.worldFromLight = Transform::translate({-1, 2, -5});
  s.lights.push_back(light);
  s.background = {0.02, 0.02, 0.05};
  s.camera.fov = 50;
  s.camera.aspect = 1.5;
  s.camera.worldFromCamera = Transform::lookAt({0, 0, -5}, {0, 0, 0}, {0, 1, 0});
  return s;
}

/// The render tests' fixture: the silhouette scene on one backend (the
/// parameter), and the other backend's kind.
class SilhouetteRender : public ::testing::TestWithParam<BackendKind> {
protected:
  Scene scene = silhouetteScene();
  std::unique_ptr<Accelerator> accel = makeAccelerator(GetParam(), scene);
  static BackendKind otherBackend() {
    return GetParam() == BackendKind::Embree ? BackendKind::KdTree : BackendKind::Embree;
  }
  /// Expects a crop of the frame `fs` renders to hold the frame's pixels.
  void expectCropIsTheFramesPixels(FrameSettings fs) {
    const Film frame = render(scene, *accel, fs);
    fs.crop = {13, 7, 37, 25};
    const Film crop = render(scene, *accel, fs);
    for (int y = fs.crop.y0; y < fs.crop.y1; ++y)
      for (int x = fs.crop.x0; x < fs.crop.x1; ++x)
        ASSERT_EQ(crop.get(x, y), frame.get(x, y)) << x << "," << y;
  }
};

} // namespace lray::test
