// Tests for src/render/camera_rays: lua/README.md, "Scene and camera" camera conventions.
#include "render/camera_rays.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

TEST(CameraRays, CentreLooksDownPlusZ) {
  Camera cam;
  CameraRays rays(cam, 100, 75);
  Ray r = rays.generate(50, 37.5);
  EXPECT_EQ(r.o, Vec3(0, 0, 0));
  EXPECT_NEAR(r.d.x, 0, 1e-12);
  EXPECT_NEAR(r.d.y, 0, 1e-12);
  EXPECT_GT(r.d.z, 0);
}

TEST(CameraRays, HorizontalFieldOfViewAndTopLeftOrigin) {
  Camera cam;
  cam.fov = 90;
  cam.aspect = 2;
  CameraRays rays(cam, 200, 100);
  Ray left = rays.generate(0, 50);
  EXPECT_NEAR(left.d.x / left.d.z, -1, 1e-12); // tan(45 deg)
  Ray topRight = rays.generate(200, 0);
  EXPECT_NEAR(topRight.d.x / topRight.d.z, 1, 1e-12);
  EXPECT_NEAR(topRight.d.y / topRight.d.z, 0.5, 1e-12); // half-height = 1 / aspect; +y is up
}

TEST(CameraRays, TransformMovesAndTurnsTheCamera) {
  Camera cam;
  cam.worldFromCamera = Transform::rotate({0, 1, 0}, 90) * Transform::translate({0, 0, -5});
  CameraRays rays(cam, 10, 10);
  Ray r = rays.generate(5, 5);
  EXPECT_NEAR(r.o.x, -5, 1e-12); // Rotate(y,90) takes -z to -x
  EXPECT_NEAR(r.o.z, 0, 1e-12);
  EXPECT_NEAR(r.d.x, 1, 1e-12); // still looking at the origin
}

} // namespace
} // namespace lray
