// Tests for src/geometry/triangle_hit: the mesh hit record both backends
// fill after their own triangle test (fillTriangleHit, meshObjectBounds).
#include "geometry/float_frame.h"
#include "geometry/shape.h"
#include "hit_expect.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace lray {
namespace {

const Vec3 kWorldOrigin(0, 0, 0);

std::shared_ptr<MeshData> oneTriangle() {
  auto m = std::make_shared<MeshData>();
  m->positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  m->triangleIndices = {0, 1, 2};
  MeshTriangle t;
  t.v[0] = 0, t.v[1] = 1, t.v[2] = 2;
  m->triangles.push_back(t);
  return m;
}

Entity meshEntity(MeshDataPtr mesh, const Transform &xf, bool smooth = false) {
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = std::move(mesh);
  e.worldFromObject = xf;
  e.smooth = smooth;
  return e;
}

TEST(FillTriangleHit, PointsNormalsAndDefaultUvsUnderATransform) {
  Transform xf = Transform::translate({1, 2, 3}) * Transform::scale(1, 1, -2);
  Entity e = meshEntity(oneTriangle(), xf);
  // Through the point with barycentrics (0.25, 0.5): object (0.5, 1, 0),
  // world (1.5, 3, 3).
  Ray ray{{1.5, 3, -4}, {0, 0, 1}};
  Hit h;
  fillTriangleHit(e, 4, 0, 7.0, 0.25, 0.5, ray, kWorldOrigin, h);
  EXPECT_EQ(h.t, 7.0);
  EXPECT_EQ(h.entity, 4u);
  EXPECT_EQ(h.primitive, 0u);
  EXPECT_EQ(h.pObject, Vec3(0.5, 1, 0));
  EXPECT_EQ(h.p, Vec3(1.5, 3, 3));
  // cross(p1 - p0, p2 - p0) = +z in object space; the mirror in z flips it.
  EXPECT_EQ(h.ng, Vec3(0, 0, -1));
  EXPECT_EQ(h.ns, h.ng);
  EXPECT_DOUBLE_EQ(h.u, 0.25);
  EXPECT_DOUBLE_EQ(h.v, 0.5);
  // At least a few float ulps of the coordinates (Embree traces in float).
  EXPECT_GE(h.pError, 4 * 0x1p-24 * 3);
  EXPECT_LT(h.pError, 1e-4);
}

TEST(FillTriangleHit, ClampsBarycentricsOntoTheTriangle) {
  Entity e = meshEntity(oneTriangle(), Transform());
  Hit h;
  fillTriangleHit(e, 0, 0, 1.0, 0.7, 0.4, {{1.4, 0.8, -1}, {0, 0, 1}}, kWorldOrigin, h);
  EXPECT_NEAR(h.pObject.x + h.pObject.y, 2, 1e-12); // on the hypotenuse
  fillTriangleHit(e, 0, 0, 1.0, -1e-7, 0.5, {{-2e-7, 1, -1}, {0, 0, 1}}, kWorldOrigin, h);
  EXPECT_EQ(h.pObject.x, 0);
}

TEST(FillTriangleHit, SmoothNormalsByVertexIndexWithoutNormalIndices) {
  auto m = oneTriangle();
  m->normals = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}; // per vertex, no MeshTriangle::n
  Entity smooth = meshEntity(m, Transform(), true);
  Hit h;
  fillTriangleHit(smooth, 0, 0, 1.0, 0.5, 0.25, {{1, 0.5, -1}, {0, 0, 1}}, kWorldOrigin, h);
  Vec3 expected = normalize(Vec3(0.5, 0.25, 0.25));
  EXPECT_NEAR(h.ns.x, expected.x, 1e-6);
  EXPECT_NEAR(h.ns.y, expected.y, 1e-6);
  EXPECT_NEAR(h.ns.z, expected.z, 1e-6);
  EXPECT_EQ(h.ng, Vec3(0, 0, 1));
  Entity flat = meshEntity(m, Transform(), false);
  fillTriangleHit(flat, 0, 0, 1.0, 0.5, 0.25, {{1, 0.5, -1}, {0, 0, 1}}, kWorldOrigin, h);
  EXPECT_EQ(h.ns, Vec3(0, 0, 1)); // smooth = false shades with the face normal
}

TEST(FillTriangleHit, GivenUvsAreInterpolated) {
  auto m = oneTriangle();
  m->uvs = {{-25, -25}, {25, -25}, {-25, 25}};
  for (int k = 0; k < 3; ++k) m->triangles[0].uv[k] = k;
  m->hasUvs = true;
  Hit h;
  fillTriangleHit(meshEntity(m, Transform()), 0, 0, 1.0, 0.5, 0.5, {{1, 1, -1}, {0, 0, 1}},
                  kWorldOrigin, h);
  EXPECT_DOUBLE_EQ(h.u, 0);
  EXPECT_DOUBLE_EQ(h.v, 0);
}

// The spawn offset (pError) covers single-precision rounding relative to the
// float frame: a triangle baked at 1e5 seen from an eye next to it gets the
// offset of a triangle at the origin, not the 1e5-sized one (which would
// jump over an occluder 1e-3 above it).
TEST(FillTriangleHit, ErrorBoundFollowsTheFloatFrame) {
  auto m = std::make_shared<MeshData>();
  m->positions = {{1e5f - 2, 1e5f, 1e5f - 2}, {1e5f + 2, 1e5f, 1e5f - 2}, {1e5f, 1e5f, 1e5f + 2}};
  m->triangleIndices = {0, 1, 2};
  MeshTriangle t;
  t.v[0] = 0, t.v[1] = 1, t.v[2] = 2;
  m->triangles.push_back(t);
  Entity baked = meshEntity(m, Transform());
  Ray down{{1e5, 1e5 + 5, 1e5}, {0, -1, 0}};
  Hit world, framed;
  fillTriangleHit(baked, 0, 0, 5.0, 0.25, 0.25, down, kWorldOrigin, world);
  fillTriangleHit(baked, 0, 0, 5.0, 0.25, 0.25, down, Vec3(1e5, 1e5 + 4, 1e5 - 6), framed);
  EXPECT_EQ(world.p, framed.p);
  EXPECT_GT(world.pError, 1e-2);
  EXPECT_LT(framed.pError, 1e-5);
  EXPECT_GT(framed.pError, 1e-7); // still covers float rounding at magnitude ~6
  // The same triangle as a transformed instance of an origin-centred mesh.
  auto local = std::make_shared<MeshData>(*m);
  for (Vec3f &p : local->positions) p = {p.x - 1e5f, p.y - 1e5f, p.z - 1e5f};
  Entity instance = meshEntity(local, Transform::translate({1e5, 1e5, 1e5}));
  Hit instWorld, instFramed;
  fillTriangleHit(instance, 0, 0, 5.0, 0.25, 0.25, down, kWorldOrigin, instWorld);
  fillTriangleHit(instance, 0, 0, 5.0, 0.25, 0.25, down, Vec3(1e5, 1e5 + 4, 1e5 - 6),
                  instFramed);
  EXPECT_GT(instWorld.pError, 1e-2);
  EXPECT_LT(instFramed.pError, 1e-5);
}

TEST(FloatFrameOrigin, TheEyeRoundedToFloatOnlyFarFromTheOrigin) {
  Scene scene;
  scene.camera.worldFromCamera = Transform::translate({3, 500, -1000});
  EXPECT_EQ(floatFrameOrigin(scene), Vec3(0, 0, 0));
  scene.camera.worldFromCamera =
      Transform::translate({0.1, 1e5 + 0.3, 0}) * Transform::rotate({0, 1, 0}, 30);
  Vec3 f = floatFrameOrigin(scene); // no entities: the eye
  EXPECT_EQ(f, Vec3(double(0.1f), double(1e5f + 0.3f), 0));
  EXPECT_EQ(f.y, double(static_cast<float>(f.y)));
}

TEST(FloatFrameOrigin, TheSceneBoxPointNearestTheEye) {
  Entity sphere;
  sphere.shape = makeShape(ShapeKind::Sphere);
  Scene scene;
  scene.entities.push_back(sphere);
  // A telephoto view of a unit sphere at the origin from 5000 away: the
  // geometry is near the origin, so the frame stays there.
  scene.camera.worldFromCamera = Transform::translate({0, 0, -5000});
  EXPECT_EQ(floatFrameOrigin(scene), Vec3(0, 0, 0));
  // The same view of the sphere moved to 1e5: the frame is on the sphere's
  // box, next to the geometry, not at the eye 5000 away.
  scene.entities[0].worldFromObject = Transform::translate({1e5, 1e5, 1e5});
  scene.camera.worldFromCamera = Transform::translate({1e5, 1e5, 1e5 - 5000});
  Vec3 f = floatFrameOrigin(scene);
  EXPECT_NEAR(f.x, 1e5, 0.01);
  EXPECT_NEAR(f.y, 1e5, 0.01);
  EXPECT_NEAR(f.z, 1e5 - 1, 0.01);
  // An eye inside the scene's box (a camera in a large scene): the eye.
  scene.entities[0].worldFromObject =
      Transform::translate({1e5, 1e5, 1e5}) * Transform::scale(100, 100, 100);
  scene.camera.worldFromCamera = Transform::translate({1e5 + 3, 1e5 + 4, 1e5 - 5});
  EXPECT_EQ(floatFrameOrigin(scene), Vec3(1e5 + 3, 1e5 + 4, 1e5 - 5));
}

// A backend's barycentrics and t (Embree's are float) are solved again in
// double from the ray: the hit is the same whatever precision found it.
TEST(FillTriangleHit, BarycentricsAreSolvedAgainInDouble) {
  Entity e = meshEntity(oneTriangle(), Transform::rotate({1, 1, 0}, 20));
  Vec3 target = e.worldFromObject.applyPoint({0.3, 0.7, 0});
  Ray ray{{0.1, -0.2, -3}, target - Vec3(0.1, -0.2, -3)};
  Hit exact, rounded;
  fillTriangleHit(e, 0, 0, 1.0, 0.15, 0.35, ray, kWorldOrigin, exact);
  fillTriangleHit(e, 0, 0, 1.0 + 3e-7, 0.15 + 2e-7, 0.35 - 1e-7, ray, kWorldOrigin, rounded);
  EXPECT_EQ(exact.t, rounded.t);
  EXPECT_EQ(exact.p, rounded.p);
  EXPECT_EQ(exact.u, rounded.u);
  EXPECT_NEAR(exact.t, 1.0, 1e-15);
  EXPECT_NEAR(exact.u, 0.15, 1e-15);
  EXPECT_NEAR(exact.v, 0.35, 1e-15);
}

TEST(FillTriangleHit, CompactCornersGiveTheSameHitAsMeshTriangles) {
  // Two triangles with vertex-indexed normals after one unrelated normal
  // (base 1), under a transform and without: reading the corners from
  // triangleIndices must not change a bit of the hit.
  auto full = std::make_shared<MeshData>();
  full->positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0.5f}, {2, 2, 1}};
  full->normals = {{1, 0, 0}, {0, 0.1f, 1}, {0.2f, 0, 1}, {0, 0, 1}, {0.1f, 0.1f, 1}};
  full->triangleIndices = {0, 1, 2, 1, 3, 2};
  for (int f = 0; f < 2; ++f) {
    MeshTriangle t;
    for (int k = 0; k < 3; ++k) {
      t.v[k] = full->triangleIndices[3 * f + k];
      t.n[k] = static_cast<int32_t>(t.v[k]) + 1;
    }
    full->triangles.push_back(t);
  }
  auto compact = std::make_shared<MeshData>(*full);
  compact->updateVertexNormalBase();
  ASSERT_EQ(compact->vertexNormalBase, 1);
  ASSERT_EQ(full->vertexNormalBase, -1);
  for (const Transform &xf :
       {Transform(), Transform::translate({1, -2, 3}) * Transform::rotate({1, 1, 0}, 30) *
                         Transform::scale(1, 2, 3)}) {
    for (uint32_t tri = 0; tri < 2; ++tri) {
      Hit a, b;
      Ray ray{{0.5, 0.5, -10}, {0, 0.1, 1}};
      fillTriangleHit(meshEntity(full, xf, true), 3, tri, 2.0, 0.25, 0.5, ray, kWorldOrigin, a);
      fillTriangleHit(meshEntity(compact, xf, true), 3, tri, 2.0, 0.25, 0.5, ray, kWorldOrigin, b);
      testing::expectSameHit(a, b);
    }
  }
}

TEST(MeshData, VertexNormalBaseOnlyWhenCornersCarryNothingElse) {
  auto m = oneTriangle();
  m->normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  for (int k = 0; k < 3; ++k) m->triangles[0].n[k] = k;
  m->updateVertexNormalBase();
  EXPECT_EQ(m->vertexNormalBase, 0);
  m->triangles[0].n[2] = 0; // normal index no longer follows the vertex
  m->updateVertexNormalBase();
  EXPECT_EQ(m->vertexNormalBase, -1);
  m->triangles[0].n[2] = 2;
  m->triangles[0].uv[0] = 0; // any uv index needs the MeshTriangle
  m->updateVertexNormalBase();
  EXPECT_EQ(m->vertexNormalBase, -1);
}

TEST(TriangleSurfacePoint, IsTheHitThereAndFixedTrianglesGiveItBitForBit) {
  // Points drawn on emitting triangles: the point and normal a hit at the
  // same barycentrics has, and the same bits from a FixedTriangle's
  // precomputed corners and normal. Vertex normals on the face's side, on
  // the other side (ng follows them), on both (the normal is worked out
  // per point), and none; placed by a shear and a mirror.
  const Transform xf = Transform::translate({1, -2, 3}) * Transform::scale(1, 2, -1) *
                       Transform::rotate({1, 1, 0}, 30);
  const std::vector<std::vector<Vec3f>> normalSets = {
      {{0, 0, 1}, {0.3f, 0, 1}, {0, 0.2f, 1}}, {{0, 0, -1}, {0, 0.5f, -1}, {0.1f, 0, -1}},
      {{0, 0, 1}, {1, 0, -0.2f}, {0, 0, -1}}, {}};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (size_t set = 0; set < normalSets.size(); ++set) {
    SCOPED_TRACE(set);
    auto m = oneTriangle();
    m->normals = normalSets[set];
    for (const Transform &placement : {Transform(), xf}) {
      const Entity e = meshEntity(m, placement, true);
      const FixedTriangle fixed(e, 0);
      for (int i = 0; i < 200; ++i) {
        const double u = unit(rng), r = std::sqrt(u), v = unit(rng);
        const double b1 = r * (1 - v), b2 = r * v;
        Vec3 p, ng, fp, fng;
        triangleSurfacePoint(e, 0, b1, b2, 0, p, ng);
        fixed.surfacePoint(b1, b2, fp, fng);
        using Bits = std::array<uint64_t, 3>;
        ASSERT_EQ(std::bit_cast<Bits>(fp), std::bit_cast<Bits>(p));
        ASSERT_EQ(std::bit_cast<Bits>(fng), std::bit_cast<Bits>(ng));
        // A hit there (a ray along the normal, met at t = 1) has them too.
        Hit h;
        fillTriangleHit(e, 0, 0, 1.0, b1, b2, {p - ng, ng, 0, 2}, kWorldOrigin, h);
        EXPECT_NEAR(length(h.p - p), 0, 1e-12);
        EXPECT_EQ(h.ng, ng);
      }
    }
  }
}

TEST(MeshObjectBounds, CoversThePositions) {
  auto m = oneTriangle();
  m->positions.push_back({-1, 5, 0.5f});
  Bounds3 b = meshObjectBounds(*m);
  EXPECT_EQ(b.lo, Vec3(-1, 0, 0));
  EXPECT_EQ(b.hi, Vec3(2, 5, 0.5));
  EXPECT_TRUE(meshObjectBounds(MeshData()).empty());
}

/// The hit records' bits: 0 and -0 (or two NaNs) must not pass for equal.
std::vector<uint64_t> hitBits(const Hit &h) {
  std::vector<uint64_t> bits;
  for (double x : {h.t, h.p.x, h.p.y, h.p.z, h.pObject.x, h.pObject.y, h.pObject.z, h.ng.x,
                   h.ng.y, h.ng.z, h.ns.x, h.ns.y, h.ns.z, h.u, h.v, h.pError})
    bits.push_back(std::bit_cast<uint64_t>(x));
  bits.push_back(h.entity);
  bits.push_back(h.primitive);
  return bits;
}

/// A random mesh of `triangles` triangles over `vertices` vertices in
/// [-scale, scale]^3, some of them repeated (degenerate triangles), with the
/// normals and uvs `kind` asks for: 0 vertex normals read by vertex index
/// (vertexNormalBase), 1 per-corner normal and uv indices, 2 no normals,
/// 3 zero vertex normals (no usable shading normal).
std::shared_ptr<MeshData> randomMesh(std::mt19937_64 &rng, int kind, double scale) {
  std::uniform_real_distribution<double> coord(-scale, scale), unit(-1, 1);
  auto m = std::make_shared<MeshData>();
  const int vertices = 40, triangles = 120;
  for (int i = 0; i < vertices; ++i)
    m->positions.push_back(toVec3f({coord(rng), coord(rng), coord(rng)}));
  for (int i = 0; i < vertices; i += 7) m->positions[i].y = -0.0f; // a zero's sign kept
  for (int i = 0; i < vertices; ++i) {
    if (kind == 3) m->normals.push_back({0, 0, 0});
    else if (kind != 2) m->normals.push_back(toVec3f({unit(rng), unit(rng), unit(rng)}));
  }
  for (int i = 0; i < vertices; ++i) m->uvs.push_back({float(unit(rng)), float(unit(rng))});
  std::uniform_int_distribution<uint32_t> pick(0, vertices - 1);
  for (int f = 0; f < triangles; ++f) {
    MeshTriangle t;
    for (int k = 0; k < 3; ++k) t.v[k] = pick(rng);
    if (f % 10 == 0) t.v[2] = t.v[0]; // degenerate: no face normal
    for (int k = 0; k < 3; ++k) {
      if (kind == 0 || kind == 3) t.n[k] = static_cast<int32_t>(t.v[k]);
      if (kind == 1) {
        t.n[k] = static_cast<int32_t>(pick(rng));
        t.uv[k] = static_cast<int32_t>(pick(rng));
      }
    }
    m->triangles.push_back(t);
    m->triangleIndices.insert(m->triangleIndices.end(), {t.v[0], t.v[1], t.v[2]});
  }
  m->hasNormals = kind != 2;
  m->updateVertexNormalBase();
  return m;
}

TEST(FillTriangleHits, BatchesMatchTheScalarFillBitForBit) {
  // The batch fill (SIMD lanes for identity-placed meshes with the frame at
  // the origin, fillTriangleHit for the rest) must give fillTriangleHit's
  // bits for every hit: both backends rely on it for identical images.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1), bary(-0.01, 0.7);
  std::vector<bool> variants{false};
  if (__builtin_cpu_supports("avx2")) variants.push_back(true);
  const Transform moved = Transform::translate({3, -1, 2}) * Transform::rotate({1, 2, 0}, 40) *
                          Transform::scale(2, 0.5, 1);
  size_t compared = 0, lanes = 0;
  for (bool avx2 : variants)
    for (int kind = 0; kind < 4; ++kind)
      for (double scale : {1e-3, 1.0, 1e4}) {
        auto mesh = randomMesh(rng, kind, scale);
        ASSERT_EQ(mesh->vertexNormalBase >= 0, kind == 0 || kind == 3);
        std::vector<Entity> entities{meshEntity(mesh, Transform(), true),
                                     meshEntity(mesh, Transform(), false),
                                     meshEntity(mesh, moved, true)};
        for (int variant = 0; variant < 4; ++variant) {
          const Vec3 frame = variant % 2 ? Vec3(1e3, -2e3, 5e2) : kWorldOrigin;
          // run 4: four queries in a row on one triangle of one mesh (a
          // floor's packet), whose corners the lanes read once.
          const int run = variant < 2 ? 1 : 4;
          const int n = 2000;
          std::vector<Ray> rays(n);
          std::vector<TriangleHitQuery> queries(n);
          std::vector<Hit> batch(n), scalar(n);
          for (int i = 0; i < n; ++i) {
            const int group = i / run;
            const uint32_t e = static_cast<uint32_t>(run > 1 ? group % 2 : i % 7 == 0 ? 2 : i % 2);
            const uint32_t tri = static_cast<uint32_t>(group * 37 % mesh->triangles.size());
            const uint32_t *v = &mesh->triangleIndices[3 * tri];
            const Vec3 p0 = toVec3(mesh->positions[v[0]]), p1 = toVec3(mesh->positions[v[1]]),
                       p2 = toVec3(mesh->positions[v[2]]);
            // A point near the triangle (barycentrics a little outside at
            // times), reached from a random origin; the backend's t and
            // barycentrics are those rounded to float.
            double b1 = bary(rng), b2 = bary(rng);
            if (i % 11 == 0) b1 = 0.5, b2 = 0.5; // the midpoint of an edge
            Vec3 target = p0 * (1 - b1 - b2) + p1 * b1 + p2 * b2;
            Vec3 d{unit(rng), unit(rng), unit(rng)};
            if (i % 13 == 0) d = p1 - p0; // in the triangle's plane
            double t = 1 + 3 * std::fabs(unit(rng));
            Ray ray{target - d * t, d};
            if (i % 5 == 0) ray.tMax = t * (1 - 1e-3); // the re-solve lands outside
            if (i % 17 == 0) ray.tMin = t * (1 + 1e-3);
            if (e == 2) ray.o = moved.applyPoint(ray.o), ray.d = moved.applyVector(ray.d);
            rays[i] = ray;
            queries[i] = {&entities[e], 9, tri, double(float(t)), double(float(b1)),
                          double(float(b2)), &rays[i], &batch[i]};
            fillTriangleHit(entities[e], 9, tri, double(float(t)), double(float(b1)),
                            double(float(b2)), rays[i], frame, scalar[i]);
            lanes += frame == kWorldOrigin && e != 2;
          }
          // Batches of 1 to 9 queries: partly filled lane groups too.
          for (int i = 0; i < n;) {
            int count = std::min(n - i, 1 + static_cast<int>(rng() % 9));
            detail::fillTriangleHits(&queries[i], static_cast<size_t>(count), frame, avx2);
            i += count;
          }
          for (int i = 0; i < n; ++i) {
            ASSERT_EQ(hitBits(batch[i]), hitBits(scalar[i]))
                << "avx2 " << avx2 << " kind " << kind << " scale " << scale << " hit " << i;
            ++compared;
          }
        }
      }
  EXPECT_GE(lanes, compared / 3);
}

} // namespace
} // namespace lray
