// Tests for src/render/camera_rays: lua/README.md, "Scene and camera" camera conventions.
#include "render/camera_rays.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <vector>

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

TEST(CameraRays, OrthographicRaysAreParallelOverItsWidth) {
  Camera cam;
  cam.kind = CameraKind::Orthographic;
  cam.width = 4;
  cam.aspect = 2;
  CameraRays rays(cam, 200, 100);
  EXPECT_FALSE(rays.hasLens());
  const Ray left = rays.generate(0, 50), topRight = rays.generate(200, 0);
  EXPECT_NEAR(left.o.x, -2, 1e-12);
  EXPECT_NEAR(topRight.o.x, 2, 1e-12);
  EXPECT_NEAR(topRight.o.y, 1, 1e-12); // width / aspect high, +y up
  EXPECT_EQ(left.d, topRight.d);
  EXPECT_EQ(left.d, Vec3(0, 0, 1));
}

TEST(CameraRays, SphericalCoversEveryDirection) {
  Camera cam;
  cam.kind = CameraKind::Spherical;
  CameraRays rays(cam, 360, 180);
  auto unit = [](const Ray &r) { return normalize(r.d); };
  const Vec3 centre = unit(rays.generate(180, 90)), right = unit(rays.generate(270, 90)),
             back = unit(rays.generate(0, 90)), up = unit(rays.generate(100, 0)),
             down = unit(rays.generate(300, 180));
  EXPECT_NEAR(centre.z, 1, 1e-12);
  EXPECT_NEAR(right.x, 1, 1e-12); // longitude 90 degrees: +x, to the right
  EXPECT_NEAR(back.z, -1, 1e-12);
  EXPECT_NEAR(up.y, 1, 1e-12);
  EXPECT_NEAR(down.y, -1, 1e-12);
  EXPECT_EQ(rays.generate(10, 20).o, Vec3(0, 0, 0));
}

TEST(CameraRays, ThinLensRaysOfAPixelMeetOnTheFocalPlane) {
  Camera cam;
  cam.fov = 60;
  cam.aspect = 1;
  cam.aperture = 0.5;
  cam.focalDistance = 3;
  cam.worldFromCamera = Transform::translate({1, 2, 3});
  CameraRays lens(cam, 64, 64);
  ASSERT_TRUE(lens.hasLens());
  cam.aperture = 0;
  CameraRays pinhole(cam, 64, 64);
  const Ray through = pinhole.generate(10.25, 40.5);
  const Vec3 onFocalPlane = through.o + through.d * 3; // d.z = 1 in camera space
  double spread = 0;
  for (double u : {0.1, 0.5, 0.93})
    for (double v : {0.05, 0.5, 0.7}) {
      const Ray r = lens.generate(10.25, 40.5, u, v);
      const double t = (onFocalPlane.z - r.o.z) / r.d.z;
      const Vec3 at = r.o + r.d * t;
      EXPECT_NEAR(at.x, onFocalPlane.x, 1e-12);
      EXPECT_NEAR(at.y, onFocalPlane.y, 1e-12);
      EXPECT_NEAR(r.o.z, 3, 1e-12); // the lens lies in the camera's z = 0 plane
      EXPECT_LE(length(r.o - Vec3(1, 2, 3)), 0.5 + 1e-12);
      spread = std::max(spread, length(r.o - Vec3(1, 2, 3)));
    }
  EXPECT_GT(spread, 0.3); // the samples reach across the lens
  // The lens centre is the pinhole.
  const Ray centre = lens.generate(10.25, 40.5, 0.5, 0.5);
  EXPECT_EQ(centre.o, through.o);
}

/// A ray's bits: 0 and -0 must not pass for equal.
std::vector<uint64_t> rayBits(const Ray &r) {
  std::vector<uint64_t> bits;
  for (double x : {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tMin, r.tMax})
    bits.push_back(std::bit_cast<uint64_t>(x));
  bits.push_back(std::bit_cast<uint32_t>(r.time));
  return bits;
}

TEST(CameraRays, ManyRaysAtOnceAreEachRayBitForBit) {
  // generateMany takes a still pinhole's rays four at a time in vector
  // lanes: each must be generate's, whatever the count (lanes left over),
  // the placement (signs of zeros, far cameras) and the kind.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(-2, 700);
  std::vector<Camera> cameras(5);
  cameras[0].fov = 45, cameras[0].aspect = 16.0 / 9;
  cameras[1].worldFromCamera = Transform::translate({1e4, -3e3, 7}) *
                               Transform::rotate({1, 2, -0.5}, 73) * Transform::scale(1, -2, 1);
  cameras[2].kind = CameraKind::Orthographic, cameras[2].width = 3;
  cameras[3].kind = CameraKind::Spherical;
  cameras[4].aperture = 0.2, cameras[4].focalDistance = 4; // a lens: its centre
  for (const Camera &cam : cameras)
    for (int n : {0, 1, 3, 4, 7, 8, 13, 256}) {
      const CameraRays rays(cam, 640, 360);
      std::vector<double> px(n), py(n);
      for (int j = 0; j < n; ++j) {
        px[j] = j % 5 == 0 ? 320 : pos(rng); // the centre column: cx = 0 (or -0)
        py[j] = j % 7 == 0 ? 180 : pos(rng);
      }
      std::vector<Ray> many(n);
      rays.generateMany(px.data(), py.data(), n, many.data());
      for (int j = 0; j < n; ++j)
        ASSERT_EQ(rayBits(many[j]), rayBits(rays.generate(px[j], py[j])))
            << "kind " << int(cam.kind) << " n " << n << " ray " << j;
    }
}

} // namespace
} // namespace lray
