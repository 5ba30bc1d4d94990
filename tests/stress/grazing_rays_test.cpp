// Robustness suite (issue 8): grazing and degenerate rays through both
// backends: tangents to every quadric (just inside must hit, just outside
// must miss), rays along the cylinder axis and the cone's generators and
// through its apex, rays in and parallel to kd-tree split planes (checked
// against brute force), zero-area and sliver triangles and duplicated
// vertices (no hit on a zero-area triangle, never a non-finite hit record).
#include "scene/mesh_builder.h"
#include "shape_params.h"
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace lray::stress {
namespace {

class StressGrazingRays : public ::testing::TestWithParam<BackendKind> {
protected:
  /// One entity of `kind` under a rotated, non-uniformly scaled, moved transform.
  void build(ShapeKind kind, bool open = false) {
    scene_ = Scene();
    Entity e = shapeEntity(kind, xf_);
    setOpen(e, open);
    scene_.entities.push_back(e);
    addDefaultMaterials(scene_);
    accel_ = makeAccelerator(GetParam(), scene_);
  }
  /// Object-space ray o + t d taken to the world (t is preserved).
  Ray worldRay(const Vec3 &o, const Vec3 &d) const {
    return {xf_.applyPoint(o), xf_.applyVector(d)};
  }
  bool hit(const Vec3 &o, const Vec3 &d, Hit &h) const {
    return accel_->intersect(worldRay(o, d), h);
  }

  Transform xf_ = Transform::translate({10, -20, 30}) * Transform::rotate({1, 2, 3}, 37) *
                  Transform::scale(2, 0.5, 3);
  Scene scene_;
  std::unique_ptr<Accelerator> accel_;
};

constexpr double kEps = 1e-6; // relative offset off tangency (object units)

TEST_P(StressGrazingRays, SphereTangents) {
  build(ShapeKind::Sphere);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  int wrong = 0, nonFinite = 0, exactHits = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    double y = 2 * u(rng) - 1, r = std::sqrt(1 - y * y), a = 2 * kPi * u(rng);
    Vec3 p{r * std::cos(a), y, r * std::sin(a)};
    // A tangent direction at p: p x (random vector), normalised.
    Vec3 t = normalize(cross(p, Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)));
    Hit h;
    if (hit(p * (1 - kEps) - t * 3, t, h)) {
      if (!hitIsFinite(h)) ++nonFinite;
    } else {
      ++wrong;
    }
    if (hit(p * (1 + kEps) - t * 3, t, h)) ++wrong;
    if (hit(p - t * 3, t, h)) {
      ++exactHits;
      if (!hitIsFinite(h) || std::fabs(h.t - 3) > 1e-3) ++nonFinite;
    }
  }
  std::printf(
      "[tangent] %-6s sphere: %d of %d inside/outside offsets wrong, %d exact tangents hit\n",
      backendName(GetParam()).c_str(), wrong, 2 * n, exactHits);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(nonFinite, 0);
}

TEST_P(StressGrazingRays, CylinderTangentsAndAxis) {
  build(ShapeKind::Cylinder);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  int wrong = 0, nonFinite = 0;
  const int n = 1000;
  for (int i = 0; i < n; ++i) {
    double a = 2 * kPi * u(rng), y = 0.1 + 0.8 * u(rng);
    Vec3 radial{std::cos(a), 0, std::sin(a)};
    Vec3 tangent{-std::sin(a), 0, std::cos(a)};
    Vec3 p = radial + Vec3(0, y, 0);
    Hit h;
    // Horizontal tangent (and tilted, within the side's height).
    for (Vec3 d : {tangent, normalize(tangent + Vec3(0, 0.05, 0))}) {
      Vec3 inside = p - radial * kEps, outside = p + radial * kEps;
      if (!hit(inside - d * 2, d, h)) ++wrong;
      else if (!hitIsFinite(h)) ++nonFinite;
      if (hit(outside - d * 2, d, h)) ++wrong;
      if (hit(p - d * 2, d, h) && !hitIsFinite(h)) ++nonFinite;
    }
    // Along a generator line of the side, from below: just inside the rim
    // enters through the bottom cap at t = 1; just outside misses; exactly
    // on the surface either, but finite.
    Vec3 up{0, 1, 0};
    if (!hit(radial * (1 - kEps) - up, up, h) || std::fabs(h.t - 1) > 1e-9) ++wrong;
    if (hit(radial * (1 + kEps) - up, up, h)) ++wrong;
    if (hit(radial - up, up, h) && !hitIsFinite(h)) ++nonFinite;
  }
  // Along the axis: from below hits the bottom cap, from inside the top cap.
  Hit h;
  ASSERT_TRUE(hit({0, -1, 0}, {0, 1, 0}, h));
  EXPECT_NEAR(h.t, 1, 1e-12);
  EXPECT_TRUE(hitIsFinite(h));
  ASSERT_TRUE(hit({0, 0.5, 0}, {0, 1, 0}, h));
  EXPECT_NEAR(h.t, 0.5, 1e-12);
  ASSERT_TRUE(hit({0, 2, 0}, {0, -1, 0}, h));
  EXPECT_NEAR(h.t, 1, 1e-12);
  std::printf("[tangent] %-6s cylinder: %d of %d offsets wrong\n", backendName(GetParam()).c_str(),
              wrong, 6 * n);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(nonFinite, 0);
  // Open: a ray along the axis meets nothing.
  build(ShapeKind::Cylinder, true);
  EXPECT_FALSE(hit({0, -1, 0}, {0, 1, 0}, h));
  EXPECT_FALSE(hit({0, 0.5, 0}, {0, 1, 0}, h));
}

TEST_P(StressGrazingRays, ConeTangentsGeneratorsAndApex) {
  build(ShapeKind::Cone);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  int wrong = 0, nonFinite = 0;
  int wrongBy[5] = {}; // tangent in, tangent out, generator in, generator out, apex
  const int n = 1000;
  for (int i = 0; i < n; ++i) {
    double a = 2 * kPi * u(rng), y = 0.1 + 0.8 * u(rng);
    Vec3 radial{std::cos(a), 0, std::sin(a)};
    Vec3 tangent{-std::sin(a), 0, std::cos(a)};
    Vec3 p = radial * (1 - y) + Vec3(0, y, 0);
    Vec3 normal = normalize(radial + Vec3(0, 1, 0));
    Hit h;
    // Horizontal tangent at p: inside/outside by a step along the normal.
    if (!hit(p - normal * kEps - tangent * 2, tangent, h)) ++wrongBy[0];
    else if (!hitIsFinite(h)) ++nonFinite;
    if (hit(p + normal * kEps - tangent * 2, tangent, h)) ++wrongBy[1];
    if (hit(p - tangent * 2, tangent, h) && !hitIsFinite(h)) ++nonFinite;
    // Along a generator (direction rim -> apex, a = 0 in the quadratic),
    // from below the base: moved towards the axis it enters through the
    // base; moved away it misses; on the surface either, but finite.
    Vec3 g = normalize(Vec3(0, 1, 0) - radial);
    Vec3 start = radial - g * 0.5;
    if (!hit(start - radial * kEps, g, h)) ++wrongBy[2];
    else if (!hitIsFinite(h)) ++nonFinite;
    if (hit(start + radial * kEps, g, h)) ++wrongBy[3];
    if (hit(start, g, h) && !hitIsFinite(h)) ++nonFinite;
    // Through the apex from above, steeper than the side: enters at the apex.
    Vec3 steep = normalize(Vec3(0, -1, 0) + radial * (0.9 * u(rng)));
    Vec3 apex{0, 1, 0};
    if (!hit(apex - steep * 2, steep, h) || std::fabs(h.t - 2) > 1e-6) ++wrongBy[4];
    else if (!hitIsFinite(h)) ++nonFinite;
    // Through the apex, shallower than the side: touches only the apex.
    Vec3 shallow = normalize(Vec3(0, -1, 0) + radial * (1.1 + u(rng)));
    if (hit(apex - shallow * 2, shallow, h) && !hitIsFinite(h)) ++nonFinite;
  }
  Hit h;
  ASSERT_TRUE(hit({0, 3, 0}, {0, -1, 0}, h)); // down the axis onto the apex
  EXPECT_NEAR(h.t, 2, 1e-9);
  EXPECT_TRUE(hitIsFinite(h));
  for (int w : wrongBy) wrong += w;
  std::printf("[tangent] %-6s cone: %d of %d wrong (tangent inside %d, outside %d; generator "
              "inside %d, outside %d; through apex %d)\n",
              backendName(GetParam()).c_str(), wrong, 5 * n, wrongBy[0], wrongBy[1], wrongBy[2],
              wrongBy[3], wrongBy[4]);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(nonFinite, 0);
}

TEST_P(StressGrazingRays, TorusTangents) {
  // Tangent lines at points of the torus' outer (convex) part, where the
  // tangent plane meets the torus nowhere else: moved inside by kEps along
  // the normal they must hit next to the point, moved outside they must miss.
  build(ShapeKind::Torus);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = 0.25;
  int wrongIn = 0, wrongOut = 0, nonFinite = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    double a = 2 * kPi * u(rng), b = (u(rng) - 0.5) * kPi * 0.88; // |phi| < 79 degrees
    double alpha = 2 * kPi * u(rng);
    Vec3 q{std::cos(a), 0, std::sin(a)};
    Vec3 normal{std::cos(b) * q.x, std::sin(b), std::cos(b) * q.z};
    Vec3 p = q + normal * r;
    Vec3 alongRing{-std::sin(a), 0, std::cos(a)};
    Vec3 alongTube{-std::sin(b) * q.x, std::cos(b), -std::sin(b) * q.z};
    Vec3 t = normalize(alongRing * std::cos(alpha) + alongTube * std::sin(alpha));
    Hit h;
    if (!hit(p - normal * (kEps * r) - t * 3, t, h)) {
      ++wrongIn;
    } else {
      if (!hitIsFinite(h)) ++nonFinite;
      Vec3 pObject = h.pObject;
      if (length(pObject - p) > 1e-2) ++wrongIn;
    }
    if (hit(p + normal * (kEps * r) - t * 3, t, h)) ++wrongOut;
  }
  // Down the axis through the hole, and along the axis of the tube circle.
  Hit h;
  EXPECT_FALSE(hit({0, 3, 0}, {0, -1, 0}, h));
  ASSERT_TRUE(hit({-3, 0, 0}, {1, 0, 0}, h));
  EXPECT_NEAR(h.t, 3 - 1.25, 1e-12);
  EXPECT_TRUE(hitIsFinite(h));
  std::printf("[tangent] %-6s torus: %d of %d wrong (inside %d, outside %d)\n",
              backendName(GetParam()).c_str(), wrongIn + wrongOut, 2 * n, wrongIn, wrongOut);
  EXPECT_EQ(wrongIn + wrongOut, 0);
  EXPECT_EQ(nonFinite, 0);
}

/// y of M^-1 (w - translation) (point) or M^-1 w (vector) in long double
/// by Cramer's rule on the stored matrix: the object-space height of a
/// world-space point or direction as the shape's own matrix defines it.
long double objectY(const Transform &xf, const Vec3 &w, bool point) {
  using LD = long double;
  const auto &m = xf.matrix().m;
  LD b[3];
  for (int i = 0; i < 3; ++i) b[i] = LD(w[i]) - (point ? LD(m[i][3]) : LD(0));
  auto det = [](LD a00, LD a01, LD a02, LD a10, LD a11, LD a12, LD a20, LD a21, LD a22) {
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) +
           a02 * (a10 * a21 - a11 * a20);
  };
  LD d = det(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  LD dy = det(m[0][0], b[0], m[0][2], m[1][0], b[1], m[1][2], m[2][0], b[2], m[2][2]);
  return dy / d;
}

TEST_P(StressGrazingRays, PlaneAtGrazingAngles) {
  // Rays 1e-3 above the plane descending at slopes down to 1e-10 meet it
  // up to 1e7 away, at t within 8 ulps of the long-double solution for the
  // world ray as given, plus the rounding of long double itself (the
  // object-space slope is a difference of O(1) terms: an absolute 2^-63 of
  // it is 2^-63 / slope relative); level or rising rays miss.
  build(ShapeKind::Plane);
  int wrong = 0;
  double worst = 0;
  for (double slope = 1e-1; slope > 1e-10; slope /= 10) {
    Hit h;
    Ray r = worldRay({0, 1e-3, 0}, normalize(Vec3(1, -slope, 0.3)));
    long double tExact = -objectY(xf_, r.o, true) / objectY(xf_, r.d, false);
    if (!accel_->intersect(r, h)) {
      ++wrong;
      continue;
    }
    double err = static_cast<double>(std::fabs((h.t - tExact) / tExact)) / 0x1p-52;
    if (slope >= 1e-4) worst = std::max(worst, err);
    double allowed = 8 + 4 * 0x1p-63 / slope / 0x1p-52;
    if (err > allowed || !hitIsFinite(h) || h.pObject.y != 0) ++wrong;
    if (hit({0, 1e-3, 0}, normalize(Vec3(1, slope, 0.3)), h)) ++wrong;
  }
  Hit h;
  EXPECT_FALSE(hit({0, 1e-3, 0}, {1, 0, 0}, h));
  std::printf("[grazing] %-6s plane: %d wrong, worst |t - t_ref| at slopes >= 1e-4 %.2f ulp(t)\n",
              backendName(GetParam()).c_str(), wrong, worst);
  EXPECT_EQ(wrong, 0);
}

TEST_P(StressGrazingRays, CubeEdgesAndFacePlanes) {
  build(ShapeKind::Cube);
  int wrong = 0, nonFinite = 0;
  const double s = 0.5;
  for (int axis = 0; axis < 3; ++axis) {
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    Vec3 d;
    d[axis] = 1;
    for (double c1 : {-s, 0.0, s})
      for (double c2 : {-s, 0.0, s}) {
        for (double nudge : {-kEps, 0.0, kEps}) {
          Vec3 o;
          o[axis] = -2;
          o[a1] = c1 * (1 + nudge);
          o[a2] = c2 * (1 + nudge);
          Hit h;
          bool got = hit(o, d, h);
          if (got && !hitIsFinite(h)) ++nonFinite;
          // Strictly inside the face's extent must hit, strictly outside must miss.
          bool inside = std::fabs(o[a1]) < s && std::fabs(o[a2]) < s;
          bool outside = std::fabs(o[a1]) > s || std::fabs(o[a2]) > s;
          if ((inside && !got) || (outside && got)) ++wrong;
          if (got && std::fabs(h.t - 1.5) > 1e-9) ++wrong;
        }
      }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(nonFinite, 0);
}

/// Closest entity by brute force over the shared shape code (analytic only).
int bruteForceEntity(const Scene &s, const Ray &r) {
  int best = -1;
  Ray q = r;
  for (size_t i = 0; i < s.entities.size(); ++i) {
    Hit h;
    if (intersectShape(s.entities[i], static_cast<uint32_t>(i), q, h)) {
      q.tMax = h.t;
      best = static_cast<int>(i);
    }
  }
  return best;
}

TEST_P(StressGrazingRays, RaysInAndParallelToSplitPlanes) {
  // A grid of axis-aligned boxes and spheres whose bounds share planes
  // (x, y, z = k +- 0.4 and k +- 0.5): the kd-tree's split candidates.
  Scene s;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 6; ++k) {
        Vec3 c(i, j, k);
        if ((i + j + k) % 3 == 0) continue;
        bool cube = (i + k) % 2 == 0;
        s.entities.push_back(shapeEntity(cube ? ShapeKind::Cube : ShapeKind::Sphere,
                                         Transform::translate(c) *
                                             (cube ? Transform::scale(0.8, 0.8, 0.8)
                                                   : Transform::scale(0.5, 0.5, 0.5))));
      }
  addDefaultMaterials(s);
  auto accel = makeAccelerator(GetParam(), s);
  int rays = 0, mismatches = 0, ties = 0, nonFinite = 0;
  const double planes[] = {-0.5, -0.4, 0.0, 0.4, 0.5};
  for (int axis = 0; axis < 3; ++axis) {
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int k1 = -1; k1 <= 6; ++k1)
      for (int k2 = -1; k2 <= 6; ++k2)
        for (double p1 : planes)
          for (double p2 : planes)
            for (int dir = 0; dir < 3; ++dir) {
              // Axis-parallel rays lying in two planes, and diagonal rays
              // lying in one (parallel to the others).
              Vec3 o, d;
              o[axis] = -3;
              o[a1] = k1 + p1;
              o[a2] = k2 + p2;
              d[axis] = 1;
              if (dir == 1) d[a1] = 0.25;
              if (dir == 2) d[a2] = -0.25;
              Ray r{o, d};
              Hit h;
              int got = accel->intersect(r, h) ? static_cast<int>(h.entity) : -1;
              if (got >= 0 && !hitIsFinite(h)) ++nonFinite;
              ++rays;
              int expected = bruteForceEntity(s, r);
              if (got == expected) continue;
              // The planes are the boxes' faces and the spheres' tangent
              // planes, so many of these rays graze a surface or run along
              // a face or edge: either answer is right there. A difference
              // is a tie when moving the ray by 1e-7 across the planes it
              // lies in gives the backend's answer.
              bool tie = false;
              for (int m = 0; m < 4 && !tie; ++m) {
                Ray moved = r;
                moved.o[m < 2 ? a1 : a2] += (m % 2 ? -1e-7 : 1e-7);
                tie = bruteForceEntity(s, moved) == got;
              }
              if (tie) {
                ++ties;
              } else {
                ++mismatches;
                if (mismatches <= 5)
                  std::printf(
                      "  mismatch: o (%g, %g, %g) d (%g, %g, %g): backend %d, brute force %d\n",
                      o.x, o.y, o.z, d.x, d.y, d.z, got, expected);
              }
            }
  }
  std::printf(
      "[split planes] %-6s: %d rays, %d disagree with brute force, %d more are grazing ties\n",
      backendName(GetParam()).c_str(), rays, mismatches, ties);
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(nonFinite, 0);
}

TEST_P(StressGrazingRays, AxisAlignedTrianglesSeenEdgeOn) {
  // Walls of triangles in the planes x = k (split candidates for both the
  // bottom-level and top-level trees) and rays lying in those planes or
  // parallel to them a hair away: nothing non-finite, and rays parallel to
  // and off every wall agree with an exact double test (which misses).
  MeshSource src;
  for (int k = 0; k < 5; ++k) {
    auto base = static_cast<int32_t>(src.positions.size());
    for (Vec3f p : {Vec3f{float(k), 0, 0}, Vec3f{float(k), 1, 0}, Vec3f{float(k), 1, 1},
                    Vec3f{float(k), 0, 1}})
      src.positions.push_back(p);
    for (int32_t c : {0, 1, 2, 0, 2, 3}) src.corners.push_back({base + c, -1, -1});
    src.faceSizes.push_back(3);
    src.faceSizes.push_back(3);
  }
  Scene s;
  s.entities.push_back(meshEntity(buildMeshData(src), Transform()));
  s.entities.push_back(meshEntity(s.entities[0].mesh, Transform::translate({0.5, 0, 3})));
  addDefaultMaterials(s);
  auto accel = makeAccelerator(GetParam(), s);
  int nonFinite = 0, offPlaneHits = 0, perpendicularMisses = 0;
  for (int k = 0; k < 5; ++k)
    for (double off : {0.0, 1e-5, -1e-5})
      for (double y = 0.05; y < 1; y += 0.1) {
        Hit h;
        // In (or beside) the plane x = k, along z through the wall.
        Ray r{{k + off, y, -1}, {0, 0, 1}};
        if (accel->intersect(r, h)) {
          if (!hitIsFinite(h)) ++nonFinite;
          if (off != 0 && h.entity == 0) ++offPlaneHits;
        }
        // Perpendicular through the wall's middle must always hit it.
        Ray across{{-1, y, 0.5}, {1, 0, 0}};
        if (!accel->intersect(across, h) || std::fabs(h.t - 1) > 1e-6) ++perpendicularMisses;
      }
  EXPECT_EQ(nonFinite, 0);
  EXPECT_EQ(offPlaneHits, 0);
  EXPECT_EQ(perpendicularMisses, 0);
}

TEST_P(StressGrazingRays, ZeroAreaAndSliverTrianglesAndDuplicatedVertices) {
  // Faces: 0 a proper triangle; 1 all three corners the same vertex;
  // 2 three distinct but equal-position vertices; 3 collinear corners;
  // 4 two corners on one vertex index; 5 a sliver 1e-7 wide; 6 a proper
  // triangle sharing vertices with the degenerate ones.
  MeshSource src;
  src.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 2, 0}, {2, 2, 0},
                   {3, 0, 0}, {4, 1, 0}, {5, 2, 0}, {3, 3, 0}, {4, 3, 0}, {3, 4, 0},
                   {3.5f, 3.5f, 1e-7f}};
  auto face = [&](std::initializer_list<int32_t> v) {
    for (int32_t i : v) src.corners.push_back({i, -1, -1});
    src.faceSizes.push_back(3);
  };
  face({0, 1, 2});
  face({3, 3, 3});
  face({3, 4, 5});
  face({6, 7, 8});
  face({9, 10, 10});
  face({10, 11, 12});
  face({3, 0, 1});
  for (bool smooth : {false, true}) {
    Scene s;
    Entity e = meshEntity(buildMeshData(src), Transform::rotate({1, 1, 0}, 20));
    e.smooth = smooth;
    s.entities.push_back(e);
    addDefaultMaterials(s);
    Light light;
    light.worldFromLight = Transform::translate({1, 2, -5});
    s.lights.push_back(light);
    auto accel = makeAccelerator(GetParam(), s);
    const Transform &xf = s.entities[0].worldFromObject;
    int nonFinite = 0, degenerateHits = 0;
    auto probe = [&](const Vec3 &objectPoint) {
      Vec3 target = xf.applyPoint(objectPoint);
      for (Vec3 from : {Vec3(0.3, 0.2, -4), Vec3(-2, 5, -3), Vec3(6, -1, 4)}) {
        Hit h;
        if (!accel->intersect({from, target - from}, h)) continue;
        if (!hitIsFinite(h)) ++nonFinite;
        if (h.primitive >= 1 && h.primitive <= 4) ++degenerateHits;
      }
    };
    for (Vec3 p : {Vec3(2, 2, 0), Vec3(4, 1, 0), Vec3(3.5, 0.5, 0), Vec3(3, 3, 0), Vec3(3.5, 3, 0),
                   Vec3(3.3, 3.6, 0), Vec3(3.25, 3.25, 0)})
      probe(p);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-0.5, 5.5);
    for (int i = 0; i < 2000; ++i) probe({u(rng), u(rng), 0});
    EXPECT_EQ(nonFinite, 0) << "smooth " << smooth;
    EXPECT_EQ(degenerateHits, 0) << "smooth " << smooth;
    // Whole-image check: the camera looks at the mesh; nothing non-finite.
    s.camera.worldFromCamera = Transform::lookAt({2, 2, -8}, {2, 2, 0}, {0, 1, 0});
    s.camera.aspect = 1;
    renderChecked(s, GetParam(), 64, 64, 2);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, StressGrazingRays, ::testing::ValuesIn(kBothBackends),
                         backendParamName);

} // namespace
} // namespace lray::stress
