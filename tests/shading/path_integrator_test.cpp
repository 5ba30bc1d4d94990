// Tests for src/shading/path_integrator (lua/README.md, "Light transport"):
// max_depth = 1 is the Whitted image without ambient, a white furnace keeps
// its energy (diffuse and Fresnel glass), emission seen directly is its
// radiance, interreflection inside a closed emitting box sums the series
// of its albedo to max_depth, and every backend renders the same frame.
#include "render/backends.h"
#include "render/renderer.h"
#include "geometry/csg_test_trees.h"
#include "shading/brute_force_accelerator.h"
#include "shading/image_cache.h"
#include "shading/quad_mesh.h"
#include "shading/rough_lobes.h"
#include "math/onb.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>

namespace lray {
namespace {

uint32_t addTexture(Scene &scene, const Finish &finish, const Color &color = {1, 1, 1}) {
  Pigment p;
  p.pattern = ColorPigment{color};
  scene.pigments.push_back(p);
  scene.textures.push_back({finish, static_cast<uint32_t>(scene.pigments.size() - 1)});
  return static_cast<uint32_t>(scene.textures.size() - 1);
}

void addEntity(Scene &scene, ShapeKind kind, const Transform &t, uint32_t texture) {
  Entity e;
  e.shape = makeShape(kind);
  e.worldFromObject = t;
  e.texture = texture;
  scene.entities.push_back(e);
}

/// Only what the lobes carry: no ambient, no highlight.
Finish matte(double diffuse) {
  Finish f;
  f.ambient = {};
  f.diffuse = diffuse;
  f.specular = 0;
  return f;
}

FrameSettings settings(int size, int samples, IntegratorKind integrator, int maxDepth = 8) {
  FrameSettings s;
  s.width = s.height = size;
  s.samples = samples;
  s.integrator = integrator;
  s.maxDepth = maxDepth;
  return s;
}

/// A frame with backend `kind` (or the tests' brute-force accelerator).
Film render(const Scene &scene, const FrameSettings &s, std::optional<BackendKind> kind = {},
            RayCounts *countsOut = nullptr) {
  ImageCache images(false);
  RayCounts local;
  RayCounts &counts = countsOut ? *countsOut : local;
  if (!kind) {
    testing::BruteForceAccelerator brute(scene, true);
    return testing::renderFrame(scene, brute, images, s, counts);
  }
  auto accel = makeAccelerator(*kind, scene);
  Film film = renderFrame(scene, *accel, images, s, counts);
  EXPECT_EQ(counts.nonFinite, 0u);
  return film;
}

/// Lit spheres and a floor under a point light, an area light and a spot.
Scene litScene(const Color &background = {}) {
  Scene s;
  s.background = background;
  Finish shiny = matte(0.7);
  shiny.specular = 0.5;
  shiny.exponent = 20;
  addEntity(s, ShapeKind::Sphere, Transform(), addTexture(s, shiny, {1, 0.5, 0.2}));
  addEntity(s, ShapeKind::Cube, Transform::translate({0, -2, 0}) * Transform::scale(6, 1, 6),
            addTexture(s, matte(0.8)));
  Light point;
  point.worldFromLight = Transform::translate({-3, 4, -3});
  s.lights.push_back(point);
  Light area;
  area.worldFromLight = Transform::translate({3, 4, -2});
  area.rows = area.cols = 3;
  area.area = true;
  area.color = {0.3, 0.3, 0.5};
  s.lights.push_back(area);
  s.camera.fov = 50;
  s.camera.aspect = 1;
  s.camera.worldFromCamera = Transform::lookAt({0, 2, -6}, {0, 0, 0}, {0, 1, 0});
  return s;
}

TEST(PathIntegrator, MaxDepthOneIsTheWhittedImageWithoutAmbient) {
  // No emitter and a black environment: with one scattering event a path
  // gathers exactly the shading equation's light from the lights. Their
  // expected values are equal; the samples differ only where an area
  // light's jitter does (the path tracer's numbers are stratified).
  const Scene scene = litScene();
  const Film whitted = render(scene, settings(24, 8, IntegratorKind::Whitted), BackendKind::Embree);
  const Film path = render(scene, settings(24, 8, IntegratorKind::Path, 1), BackendKind::Embree);
  int lit = 0;
  double whittedSum = 0, pathSum = 0, pathRed = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const Color a = path.get(x, y), b = whitted.get(x, y);
      EXPECT_NEAR(a.r, b.r, 0.02) << x << ", " << y;
      EXPECT_NEAR(a.b, b.b, 0.02) << x << ", " << y;
      lit += a.r > 0.3;
      pathSum += a.r + a.g + a.b;
      whittedSum += b.r + b.g + b.b;
      pathRed += a.r;
    }
  EXPECT_GT(lit, 50);
  EXPECT_NEAR(pathSum / whittedSum, 1, 1e-3);
  // Without the area light every sample is the same in both.
  Scene pointOnly = scene;
  pointOnly.lights.pop_back();
  const Film w1 = render(pointOnly, settings(24, 2, IntegratorKind::Whitted), BackendKind::Embree);
  const Film p1 = render(pointOnly, settings(24, 2, IntegratorKind::Path, 1), BackendKind::Embree);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) ASSERT_EQ(p1.get(x, y), w1.get(x, y)) << x << ", " << y;
  // Deeper paths add the light the surfaces pass on, never take any away.
  const Film deeper = render(scene, settings(24, 8, IntegratorKind::Path, 4), BackendKind::Embree);
  double deepRed = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) deepRed += deeper.get(x, y).r;
  EXPECT_GT(deepRed, pathRed * 1.05);
}

/// A white environment around `finish` on a torus (concave: paths bounce
/// on it more than once) and a sphere: without lights or absorption, an
/// object that keeps its energy is invisible.
void expectWhiteFurnace(const Finish &finish, int maxDepth, double tolerance) {
  Scene s;
  s.background = {1, 1, 1};
  const uint32_t t = addTexture(s, finish);
  addEntity(s, ShapeKind::Torus, Transform::rotate({1, 0, 0}, -60), t);
  addEntity(s, ShapeKind::Sphere, Transform::translate({0, 0, 0}) * Transform::scale(0.3, 0.3, 0.3),
            t);
  s.camera.fov = 60;
  s.camera.aspect = 1;
  s.camera.worldFromCamera = Transform::translate({0, 0, -3});
  const Film film = render(s, settings(16, 4, IntegratorKind::Path, maxDepth), BackendKind::Embree);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const Color c = film.get(x, y);
      EXPECT_NEAR(c.r, 1, tolerance) << x << ", " << y;
      EXPECT_NEAR(c.g, 1, tolerance) << x << ", " << y;
    }
}

/// Glass that keeps its energy: reflection F and refraction 1 - F, no absorption.
Finish clearGlass() {
  Finish glass = matte(0);
  glass.reflection = 1;
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.absorption = 0;
  glass.fresnel = true;
  return glass;
}

TEST(PathIntegrator, AWhiteFurnaceIsInvisible) {
  // Albedo 1: every path ends in the environment with throughput 1.
  expectWhiteFurnace(matte(1), 64, 1e-9);
  // Fresnel glass: reflection F and refraction 1 - F sum to 1.
  Finish glass = clearGlass();
  expectWhiteFurnace(glass, 64, 1e-9);
  // Albedo 0.5 in a white furnace is darker: the control.
  Scene s;
  s.background = {1, 1, 1};
  addEntity(s, ShapeKind::Sphere, Transform(), addTexture(s, matte(0.5)));
  s.camera.worldFromCamera = Transform::translate({0, 0, -3});
  s.camera.aspect = 1;
  const Film film = render(s, settings(8, 1, IntegratorKind::Path), BackendKind::Embree);
  EXPECT_NEAR(film.get(4, 4).r, 0.5, 1e-12); // a convex object: one bounce, then the sky
}

/// A closed box of two triangles per face, its normals facing in.
MeshDataPtr inwardBox() {
  auto mesh = std::make_shared<MeshData>();
  for (int i = 0; i < 8; ++i)
    mesh->positions.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto &f : faces)
    for (const auto &tri : {std::array<int, 3>{f[0], f[1], f[2]}, {f[0], f[2], f[3]}}) {
      MeshTriangle t{{uint32_t(tri[0]), uint32_t(tri[1]), uint32_t(tri[2])}};
      const Vec3 a = toVec3(mesh->positions[tri[0]]), b = toVec3(mesh->positions[tri[1]]),
                 c = toVec3(mesh->positions[tri[2]]);
      // The geometric normal is cross(b - a, c - a): turn it towards the centre.
      if (dot(cross(b - a, c - a), a + b + c) > 0) std::swap(t.v[1], t.v[2]);
      mesh->triangles.push_back(t);
      mesh->triangleIndices.insert(mesh->triangleIndices.end(), t.v, t.v + 3);
    }
  return mesh;
}

TEST(PathIntegrator, InsideAnEmittingBoxTheAlbedoSeriesSumsToMaxDepth) {
  // Emission E = 1 and albedo 0.5 everywhere: light that scattered k times
  // arrives weighted 0.5^k, so the radiance is the series 1 + 0.5 + ... to
  // 0.5^max_depth. The box is its own emitter: sampled directly and by the
  // bounces, weighted by MIS, with Russian roulette from the third vertex;
  // the expected value is the series either way.
  Scene s;
  Finish f = matte(0.5);
  f.emission = {1, 1, 1};
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = inwardBox();
  e.texture = addTexture(s, f);
  s.entities.push_back(e);
  s.camera.aspect = 1;
  for (int depth : {1, 2, 3, 8}) {
    SCOPED_TRACE(depth);
    constexpr int kSize = 16;
    const Film film =
        render(s, settings(kSize, 8, IntegratorKind::Path, depth), BackendKind::KdTree);
    double sum = 0, squares = 0; // over pixels of 64 samples each
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        sum += film.get(x, y).g;
        squares += film.get(x, y).g * film.get(x, y).g;
      }
    const double n = kSize * kSize, mean = sum / n;
    const double expected = (1 - std::pow(0.5, depth + 1)) / 0.5;
    // Within 4 standard errors of the pixels' mean (and the error small).
    const double standardError = std::sqrt(std::max(0.0, squares / n - mean * mean) / (n - 1));
    EXPECT_LT(standardError, 0.01);
    EXPECT_NEAR(mean, expected, 4 * standardError);
  }
}

/// Where litSquare's camera looks at its square from.
const Vec3 kSquareViewer(0.5, 1, 0);

/// Adds a small square of `finish` at the origin facing +y, seen alone by
/// the camera from kSquareViewer, renders the direct light on it
/// (max_depth 1) and returns its mean value and that mean's standard error.
std::pair<double, double> litSquare(Scene &s, const Finish &finish, int samples = 16) {
  testing::addQuad(s, {Vec3f{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, addTexture(s, finish),
                   Transform::scale(0.01, 1, 0.01)); // normal +y
  s.camera.fov = 0.5; // the square fills the view
  s.camera.aspect = 1;
  s.camera.worldFromCamera = Transform::lookAt(kSquareViewer, {0, 0, 0}, {0, 1, 0});
  constexpr int kSize = 8;
  const Film film =
      render(s, settings(kSize, samples, IntegratorKind::Path, 1), BackendKind::Embree);
  double sum = 0, squares = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      sum += film.get(x, y).r;
      squares += film.get(x, y).r * film.get(x, y).r;
    }
  const double n = kSize * kSize, mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, squares / n - mean * mean) / (n - 1))};
}

TEST(PathIntegrator, ASphericalEmitterLightsAPointAsItsSolidAngleSays) {
  // A small matte square facing an emitting sphere of radius R, radiance L,
  // centre at distance d: irradiance pi L (R / d)^2, so the square shows
  // albedo * L * (R / d)^2 (max_depth 1: the direct light alone). The
  // sphere is placed by a rotation and a uniform scale: still a sphere, it
  // is sampled by the cone of directions it fills, which makes the square
  // nearly noiseless (by area: 100 times the standard error).
  Scene s;
  const double R = 0.5, d = 2, L = 4, albedo = 0.8;
  Finish lamp = matte(0);
  lamp.emission = {L, L, L};
  addEntity(s, ShapeKind::Sphere,
            Transform::translate({0, d, 0}) * Transform::rotate({1, 1, 0}, 30) *
                Transform::scale(R, R, R),
            addTexture(s, lamp));
  const auto [mean, standardError] = litSquare(s, matte(albedo));
  EXPECT_NEAR(mean, albedo * L * (R / d) * (R / d), 4 * standardError + 1e-3);
  EXPECT_LT(standardError, 1e-4); // by area: 0.0024; by the cone it fills: 2.5e-5
}

TEST(PathIntegrator, CylinderAndConeEmittersLightAPointAsTheirBaseDiskSays) {
  // The base of a cylinder or cone (radius R, radiance L) faces the square
  // from height d: a disk on the axis gives irradiance pi L R^2 / (d^2 +
  // R^2); their sides face away. Non-uniform scales and a turn about the
  // axis: the object-space samples' density must follow them to world area.
  for (ShapeKind kind : {ShapeKind::Cylinder, ShapeKind::Cone}) {
    SCOPED_TRACE(kind == ShapeKind::Cylinder ? "cylinder" : "cone");
    Scene s;
    const double R = 0.6, d = 1.5, L = 3, albedo = 0.7;
    Finish lamp = matte(0);
    lamp.emission = {L, L, L};
    addEntity(s, kind,
              Transform::translate({0, d, 0}) * Transform::rotate({0, 1, 0}, 40) *
                  Transform::scale(R, 0.4, R),
              addTexture(s, lamp));
    const auto [mean, standardError] = litSquare(s, matte(albedo));
    EXPECT_NEAR(mean, albedo * L * R * R / (d * d + R * R), 4 * standardError + 1e-3);
    EXPECT_LT(standardError, 0.01);
  }
}

TEST(PathIntegrator, ATorusEmitterLightsAPointAsItsSurfaceIntegralSays) {
  // A ring torus (R = 1, r = 0.3) and a spindle torus (R = 0.3, r = 0.5:
  // an apple whose surface is the tube's part with R + r cos b >= 0),
  // scaled by k = 0.8 and turned about their axis, emitting L, level at
  // height d over the square: the irradiance at the square is the integral
  // of L cos_s cos_l / dist^2 over the part of the surface facing it (none
  // of it is hidden from a point on the axis), by quadrature over the
  // tube's angles. Their points are drawn in object space by inverting the
  // distribution of the tube angle; the small standard error says they are
  // (measured 1.5e-5 and 1.4e-5 of the value; the spindle found by bounces
  // alone, 4.6e-4).
  struct Case {
    const char *name;
    double R, r, b0, b1;
  };
  const double apple = std::acos(-0.3 / 0.5);
  for (const Case &c : {Case{"ring", 1, 0.3, 0, 2 * std::numbers::pi},
                        Case{"spindle", 0.3, 0.5, -apple, apple}}) {
    SCOPED_TRACE(c.name);
    Scene s;
    const double k = 0.8, d = 1.5, L = 3, albedo = 0.7;
    Finish lamp = matte(0);
    lamp.emission = {L, L, L};
    Entity torus;
    torus.shape = Torus{c.R, c.r};
    torus.worldFromObject = Transform::translate({0, d, 0}) *
                            Transform::rotate({0, 1, 0}, 30) * Transform::scale(k, k, k);
    torus.texture = addTexture(s, lamp);
    s.entities.push_back(torus);
    const auto [mean, standardError] = litSquare(s, matte(albedo), 32);
    double irradiance = 0;
    constexpr int kSteps = 2000;
    for (int j = 0; j < kSteps; ++j) { // the tube angle b; the ring angle integrates to 2 pi
      const double step = (c.b1 - c.b0) / kSteps, b = c.b0 + step * (j + 0.5);
      const Vec3 p(k * (c.R + c.r * std::cos(b)), d + k * c.r * std::sin(b), 0);
      const Vec3 n(std::cos(b), std::sin(b), 0);
      const double dist2 = dot(p, p), dist = std::sqrt(dist2);
      const double cosSquare = p.y / dist, cosLight = -dot(n, p) / dist;
      if (cosLight <= 0) continue;
      const double area =
          k * k * c.r * (c.R + c.r * std::cos(b)) * 2 * std::numbers::pi * step;
      irradiance += L * cosSquare * cosLight / dist2 * area;
    }
    const double expected = albedo / std::numbers::pi * irradiance;
    EXPECT_NEAR(mean, expected, 4 * standardError + 1e-3 * expected);
    EXPECT_LT(standardError, 1e-4 * expected);
  }
}

TEST(PathIntegrator, CsgEmittersAreSampledWhereTheResultShowsThem) {
  // An emitting sphere (radius R, L1 = 5) minus a cube whose top face halves
  // it, the cube's leaf emitting L2 = 3: the result is the upper half-ball,
  // closed below by a disk of the cube's face that faces down at height d.
  // From the square below only the disk is seen: albedo L2 R^2 / (d^2 +
  // R^2). Points drawn on the sphere's lower half or on the cube's other
  // faces are not the result's surface and must count nothing (else the
  // removed half of the sphere and the cube's bottom would light it).
  Scene s;
  const double R = 0.5, d = 1.5, albedo = 0.7;
  Finish sphereLamp = matte(0), cubeLamp = matte(0);
  sphereLamp.emission = {5, 5, 5};
  cubeLamp.emission = {3, 3, 3};
  test::CsgSpec sphere = test::leafSpec(ShapeKind::Sphere, Transform::translate({0, d, 0}) *
                                                               Transform::scale(R, R, R));
  sphere.leaf.texture = addTexture(s, sphereLamp);
  test::CsgSpec cube = test::leafSpec(ShapeKind::Cube, Transform::translate({0, d - 1, 0}) *
                                                           Transform::scale(2, 2, 2));
  cube.leaf.texture = addTexture(s, cubeLamp);
  Entity csg = test::csgEntity(test::opSpec(CsgOp::Difference, {sphere, cube}));
  csg.texture = sphere.leaf.texture;
  s.entities.push_back(csg);
  const auto [mean, standardError] = litSquare(s, matte(albedo), 32);
  const double expected = albedo * 3 * R * R / (d * d + R * R);
  EXPECT_NEAR(mean, expected, 4 * standardError + 1e-3 * expected);
  EXPECT_LT(standardError, 0.02 * expected); // most points drawn are rejected (the cube's)
}

/// A diffuse and rough square's finish (reflection alone, no Fresnel).
Finish glossy(double roughness) {
  Finish f = matte(0.3);
  f.reflection = 0.7;
  f.roughness = roughness;
  return f;
}

/// What `finish` on litSquare's square sends its viewer of the light of a
/// sphere of radius R, radiance L, centred at `centre`: the lobes' fcos
/// integrated over the sphere's cone of directions by quadrature.
double glossyUnderSphere(const Finish &finish, const Vec3 &centre, double R, double L) {
  const Vec3 n(0, 1, 0), wo = normalize(kSquareViewer);
  const RoughLobes rough(finish, true, false, 1.0);
  const double d = length(centre), cosMax = std::sqrt(1 - R * R / (d * d));
  Vec3 t, b;
  orthonormalBasis(centre / d, t, b);
  constexpr int kU = 600, kPhi = 600;
  double sum = 0;
  for (int i = 0; i < kU; ++i) {
    const double c = cosMax + (1 - cosMax) * (i + 0.5) / kU, r = std::sqrt(1 - c * c);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2 * std::numbers::pi * (j + 0.5) / kPhi;
      const Vec3 wi = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + centre / d * c;
      const double diffuse = finish.diffuse * std::max(0.0, dot(n, wi)) / std::numbers::pi;
      sum += (diffuse + rough.evaluate(n, wo, wi).fcos) * (1 - cosMax) / kU * 2 *
             std::numbers::pi / kPhi;
    }
  }
  return sum * L;
}

TEST(PathIntegrator, EmittersLightRoughLobesWeightedByMisToTheirIntegral) {
  // A rough reflector sees an emitting sphere in its mirror direction:
  // small and far (emitter sampling finds it best), then large and near
  // under a narrower lobe (sampling the lobe does). Both strategies count,
  // weighted by MIS: unless the weights sum to one where both can find a
  // point, the mean misses the integral of the lobes over the sphere.
  const Vec3 mirror = normalize(Vec3(-kSquareViewer.x, kSquareViewer.y, 0));
  struct Lamp {
    double roughness, R, distance;
  };
  for (const Lamp lamp : {Lamp{0.2, 0.15, 3}, Lamp{0.05, 1.1, 1.6}}) {
    SCOPED_TRACE(lamp.R);
    Scene s;
    const double L = 5;
    Finish emit = matte(0);
    emit.emission = {L, L, L};
    const Vec3 centre = mirror * lamp.distance;
    addEntity(s, ShapeKind::Sphere, Transform::translate(centre) *
                                        Transform::scale(lamp.R, lamp.R, lamp.R),
              addTexture(s, emit));
    const Finish f = glossy(lamp.roughness);
    const auto [mean, standardError] = litSquare(s, f, 64);
    const double expected = glossyUnderSphere(f, centre, lamp.R, L);
    EXPECT_NEAR(mean, expected, 4 * standardError + 5e-4 * expected);
    EXPECT_LT(standardError, 3e-3 * expected);
  }
}

TEST(PathIntegrator, LightsAreSeenInRoughLobes) {
  // A point Light of colour Lc gives irradiance pi Lc cos: the rough lobe
  // adds pi Lc fcos to the shading equation's diffuse Lc cos (no
  // highlight), also where there is no diffuse lobe at all. The light is
  // the only sample: the image is exact.
  const Vec3 toLight = normalize(Vec3(-0.45, 1, 0.1));
  for (double diffuse : {0.3, 0.0}) {
    SCOPED_TRACE(diffuse);
    Scene s;
    Light light;
    light.color = {0.8, 0.6, 0.4};
    light.worldFromLight = Transform::translate(toLight * 4);
    s.lights.push_back(light);
    Finish f = glossy(0.3);
    f.diffuse = diffuse;
    const auto [mean, standardError] = litSquare(s, f);
    const RoughLobes rough(f, true, false, 1.0);
    const double fcos = rough.evaluate({0, 1, 0}, normalize(kSquareViewer), toLight).fcos;
    EXPECT_GT(fcos, 0.3);
    EXPECT_NEAR(mean, 0.8 * (f.diffuse * toLight.y + std::numbers::pi * fcos), 2e-3);
    EXPECT_LT(standardError, 2e-3);
  }
}

/// A unit sphere of `finish` at the origin under a constant sky, seen from
/// `distance` down +z with a square image.
Scene sphereInSky(const Finish &finish, const Color &sky, double distance = 3) {
  Scene s;
  s.background = sky;
  addEntity(s, ShapeKind::Sphere, Transform(), addTexture(s, finish));
  s.camera.worldFromCamera = Transform::translate({0, 0, -distance});
  s.camera.aspect = 1;
  return s;
}

TEST(PathIntegrator, EmissionSeenDirectlyIsItsRadiance) {
  Finish lamp = matte(0);
  lamp.emission = {3, 2, 1};
  const Scene s = sphereInSky(lamp, {0.3, 0.3, 0.3}, 4);
  const Film film = render(s, settings(9, 1, IntegratorKind::Path), BackendKind::Embree);
  EXPECT_EQ(film.get(4, 4), Color(3, 2, 1));
  EXPECT_NEAR(film.get(0, 0).g, 0.3, 1e-7); // the environment, seen directly (a float film)
}

/// The mean and largest channel of a white furnace's image of `finish`.
std::pair<double, double> furnaceMeanAndMax(const Finish &finish, IntegratorKind integrator) {
  Scene s;
  s.background = {1, 1, 1};
  addEntity(s, ShapeKind::Sphere, Transform(), addTexture(s, finish));
  s.camera.fov = 40;
  s.camera.aspect = 1;
  s.camera.worldFromCamera = Transform::translate({0, 0, -3});
  const Film film = render(s, settings(16, 16, integrator, 64), BackendKind::Embree);
  double sum = 0, largest = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const Color c = film.get(x, y);
      sum += c.r;
      largest = std::max({largest, c.r, c.g, c.b});
    }
  return {sum / 256, largest};
}

TEST(PathIntegrator, RoughLobesKeepAllButTheirShadowedEnergy) {
  // GGX with single scattering loses what its microfacets shadow (most at
  // grazing angles, the sphere's rim) and may never gain: the furnace stays
  // at or below 1, loses more the rougher it is, and nothing measurable
  // when nearly smooth.
  Finish mirror = matte(0);
  mirror.reflection = 1;
  Finish glass = clearGlass();
  for (Finish f : {mirror, glass})
    for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
      SCOPED_TRACE(std::string(f.refraction > 0 ? "glass " : "mirror ") +
                   (kind == IntegratorKind::Path ? "path" : "whitted"));
      f.roughness = 0.3;
      const auto [mean, largest] = furnaceMeanAndMax(f, kind);
      EXPECT_LE(largest, 1 + 1e-9);
      EXPECT_GT(mean, 0.7);
      EXPECT_LT(mean, 1);
      f.roughness = 0.6;
      EXPECT_LT(furnaceMeanAndMax(f, kind).first, mean);
      f.roughness = 0.001;
      const double nearlySmooth = furnaceMeanAndMax(f, kind).first;
      f.roughness = 0; // 1, or what the Whitted integrator's depth limit leaves
      EXPECT_NEAR(nearlySmooth, furnaceMeanAndMax(f, kind).first, 1e-3);
    }
}

TEST(PathIntegrator, StatsCountPathsAndTheSurfacesTheyMeet) {
  // A convex matte sphere in a sky: a path that hits it scatters once, into
  // the sky (two-surface paths are impossible), one that misses meets none.
  const Scene s = sphereInSky(matte(0.5), {1, 1, 1});
  RayCounts counts;
  render(s, settings(16, 2, IntegratorKind::Path), BackendKind::Embree, &counts);
  EXPECT_EQ(counts.paths, 16u * 16 * 4);
  EXPECT_EQ(counts.pathVertices, counts.diffuse);
  EXPECT_GT(counts.pathVertices, counts.paths / 4);
  EXPECT_LT(counts.pathVertices, counts.paths);
}

TEST(PathIntegrator, ClampScalesEachSampleDownKeepingItsHue) {
  Finish lamp = matte(0);
  lamp.emission = {8, 4, 2};
  const Scene s = sphereInSky(lamp, {0.5, 0.25, 0.125});
  FrameSettings clamped = settings(8, 1, IntegratorKind::Path);
  clamped.clamp = 1;
  const Film plain = render(s, settings(8, 1, IntegratorKind::Path), BackendKind::Embree);
  const Film film = render(s, clamped, BackendKind::Embree);
  EXPECT_NEAR(plain.get(4, 4).r, 8, 1e-12);
  EXPECT_NEAR(film.get(4, 4).r, 1, 1e-12);  // the lamp, seen directly
  EXPECT_NEAR(film.get(4, 4).g, 0.5, 1e-12); // the same hue
  EXPECT_NEAR(film.get(0, 0).r, 0.5, 1e-12); // the sky is below the clamp
  clamped.clamp = 100;
  EXPECT_NEAR(render(s, clamped, BackendKind::Embree).get(4, 4).r, 8, 1e-12);
}

TEST(PathIntegrator, AovsAreThoseOfTheFirstSurfaceThatIsNotAPerfectMirror) {
  // A mirror sphere under a sky, a red matte sphere behind a glass one:
  // the path tracer's albedo is what the mirror and the glass show (as
  // denoisers want it), the Whitted one's the first surface's pigment.
  Finish mirror = matte(0);
  mirror.reflection = 1;
  Scene s = sphereInSky(mirror, {0.2, 0.4, 0.6});
  FrameSettings path = settings(9, 1, IntegratorKind::Path), whitted = path;
  whitted.integrator = IntegratorKind::Whitted;
  path.aovs = whitted.aovs = true;
  const Film mirrored = render(s, path, BackendKind::Embree);
  const Film::Aov &a = mirrored.aov(4, 4);
  EXPECT_NEAR(a.albedo[0], 0.2, 1e-6);
  EXPECT_NEAR(a.albedo[2], 0.6, 1e-6);
  EXPECT_NEAR(render(s, whitted, BackendKind::Embree).aov(4, 4).albedo[0], 1, 1e-6);

  s = sphereInSky(clearGlass(), {0, 0, 0});
  const uint32_t t = addTexture(s, matte(1), {0.9, 0.1, 0.1});
  addEntity(s, ShapeKind::Sphere, Transform::translate({0, 0, 6}) * Transform::scale(3, 3, 3), t);
  const Film film = render(s, path, BackendKind::Embree);
  EXPECT_NEAR(film.aov(4, 4).albedo[0], 0.9, 1e-6);
  EXPECT_NEAR(film.aov(4, 4).albedo[1], 0.1, 1e-6);
  EXPECT_LT(film.aov(4, 4).n[2], 0); // the red sphere's front faces the camera
}

TEST(PathIntegrator, EveryBackendRendersTheSameFrame) {
  Scene s = litScene();
  Finish glass = matte(0.1);
  glass.reflection = 1;
  glass.refraction = 1;
  glass.refractionIndex = 1.5;
  glass.fresnel = true;
  addEntity(s, ShapeKind::Sphere,
            Transform::translate({1.5, 0, -1}) * Transform::scale(0.5, 0.5, 0.5),
            addTexture(s, glass));
  Finish lamp = matte(0.5);
  lamp.emission = {2, 2, 1};
  addEntity(s, ShapeKind::Cylinder,
            Transform::translate({-1.5, 0, -1}) * Transform::scale(0.3, 0.8, 0.3),
            addTexture(s, lamp));
  const FrameSettings fs = settings(20, 2, IntegratorKind::Path);
  const Film embree = render(s, fs, BackendKind::Embree);
  const Film kdtree = render(s, fs, BackendKind::KdTree);
  const Film brute = render(s, fs);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      ASSERT_EQ(kdtree.get(x, y), embree.get(x, y)) << x << ", " << y;
      ASSERT_EQ(brute.get(x, y), embree.get(x, y)) << x << ", " << y;
    }
}

using testing::addQuad;

TEST(PathIntegrator, AnEmittingTriangleDoesNotShadowItsOwnLight) {
  // A floor under an emitting square: the shadow rays to points on the
  // square end at its surface, where a single-precision test (Embree's
  // triangles) finds the square itself unless they stop short of it by
  // more than its error. They did not: squares of shadow on the floor,
  // on Embree alone. Both backends and the brute-force tests agree now.
  Scene s;
  addQuad(s, {Vec3f{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, addTexture(s, matte(0.7)));
  Finish lamp = matte(0);
  lamp.emission = {4, 4, 4};
  addQuad(s, {Vec3f{-0.25f, 1.98f, -0.25f}, {0.25f, 1.98f, -0.25f}, {0.25f, 1.98f, 0.25f},
              {-0.25f, 1.98f, 0.25f}},
          addTexture(s, lamp)); // facing down
  s.camera.fov = 40;
  s.camera.aspect = 1;
  s.camera.worldFromCamera = Transform::lookAt({0, 1, -3.9}, {0, 1, 0}, {0, 1, 0});
  const FrameSettings fs = settings(48, 2, IntegratorKind::Path, 1);
  const Film embree = render(s, fs, BackendKind::Embree);
  const Film kdtree = render(s, fs, BackendKind::KdTree);
  const Film brute = render(s, fs);
  int lit = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      ASSERT_EQ(kdtree.get(x, y), embree.get(x, y)) << x << ", " << y;
      ASSERT_EQ(brute.get(x, y), embree.get(x, y)) << x << ", " << y;
      lit += embree.get(x, y).r > 0.005 && embree.get(x, y).r < 1;
    }
  EXPECT_GT(lit, 300); // the floor
}

} // namespace
} // namespace lray
