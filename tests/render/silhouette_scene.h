// Test helper for the render tests: a small scene of silhouettes and
// smooth shading on a flat background.
#pragma once

#include "scene/scene.h"

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

} // namespace lray::test
