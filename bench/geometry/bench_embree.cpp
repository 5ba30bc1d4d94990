// Benchmark for the Embree backend (src/accel/embree): primary rays on a
// ~1M-triangle mesh and on 1e5 analytic shapes, raw Embree (a minimal loop
// of rtcIntersect1 / rtcIntersect8, no hit record) against LRay's
// EmbreeAccelerator (intersect / intersectCoherent, full Hit); plus memory
// per triangle and the cost of an instance. Single thread; ray rates are
// medians of seven rounds in thread CPU time, each round timing all four
// loops one after the other, so that the shared machine's drift hits raw
// Embree and LRay alike.
//
//   bench_embree [width height]     (default 1024 x 768 rays per view)
#include "accel/embree/embree_accelerator.h"
#include "geometry/shape.h"
#include "render/renderer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <memory>
#include <random>
#include <tuple>
#include <vector>

namespace lray {
namespace {

/// CPU time of the calling thread: steadier than wall time on a shared
/// machine (time slices given to other processes do not count).
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// A wavy terrain over [-1, 1]^2 (xz) with (n+1)^2 vertices, 2 n^2 triangles,
/// per-vertex normals indexed like the scene layer does.
std::shared_ptr<MeshData> makeTerrain(int n) {
  auto m = std::make_shared<MeshData>();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = -1 + 2.0 * i / n, z = -1 + 2.0 * j / n;
      double y = 0.1 * std::sin(7 * x) * std::cos(5 * z) + jitter(rng);
      m->positions.push_back({float(x), float(y), float(z)});
      m->normals.push_back({0, 1, 0});
    }
  auto idx = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      uint32_t a = idx(i, j), b = idx(i + 1, j), c = idx(i + 1, j + 1), d = idx(i, j + 1);
      for (auto [p, q, r] : {std::tuple{a, d, c}, std::tuple{a, c, b}}) {
        MeshTriangle t;
        t.v[0] = p, t.v[1] = q, t.v[2] = r;
        for (int k = 0; k < 3; ++k) t.n[k] = static_cast<int32_t>(t.v[k]);
        m->triangles.push_back(t);
        m->triangleIndices.insert(m->triangleIndices.end(), {p, q, r});
      }
    }
  m->updateVertexNormalBase(); // as the scene layer's buildMeshData does
  return m;
}

/// Camera rays (pinhole at `eye` looking at `at`, horizontal fov 60 deg) in
/// the renderer's order: 16x16-pixel tiles (render/renderer.h kTileSize),
/// row-major within a tile, so consecutive runs of 8 are coherent and a
/// tile's rays are one intersectCoherent call, as the renderer makes it.
std::vector<Ray> cameraRays(const Vec3 &eye, const Vec3 &at, int w, int h) {
  Transform cam = Transform::lookAt(eye, at, {0, 1, 0});
  double tanHalf = std::tan(30.0 * 3.14159265358979323846 / 180);
  std::vector<Ray> rays;
  rays.reserve(static_cast<size_t>(w) * h);
  for (int ty = 0; ty < h; ty += kTileSize)
    for (int tx = 0; tx < w; tx += kTileSize)
      for (int y = ty; y < std::min(ty + kTileSize, h); ++y)
        for (int x = tx; x < std::min(tx + kTileSize, w); ++x) {
          double sx = (2 * (x + 0.5) / w - 1) * tanHalf;
          double sy = (1 - 2 * (y + 0.5) / h) * tanHalf * h / w;
          rays.push_back({eye, normalize(cam.applyVector({sx, sy, 1}))});
        }
  return rays;
}

// --- Raw Embree: the same geometry with the least possible glue -------------

struct RawShapes {
  const std::vector<Entity> *entities;
};

void rawBounds(const RTCBoundsFunctionArguments *args) {
  const auto *s = static_cast<const RawShapes *>(args->geometryUserPtr);
  Bounds3 b = shapeWorldBounds((*s->entities)[args->primID]);
  *args->bounds_o = {float(b.lo.x), float(b.lo.y), float(b.lo.z), 0,
                     float(b.hi.x), float(b.hi.y), float(b.hi.z), 0};
}

void rawIntersect(const RTCIntersectFunctionNArguments *args) {
  const auto *s = static_cast<const RawShapes *>(args->geometryUserPtr);
  RTCRayN *ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN *hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    Ray r{{RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
           RTCRayN_org_z(ray, args->N, i)},
          {RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
           RTCRayN_dir_z(ray, args->N, i)},
          RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i)};
    Hit h;
    if (!intersectShape((*s->entities)[args->primID], args->primID, r, h)) continue;
    RTCRayN_tfar(ray, args->N, i) = float(h.t);
    RTCHitN_primID(hit, args->N, i) = args->primID;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
  }
}

void rawOccluded(const RTCOccludedFunctionNArguments *) {}

struct RawScene {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = nullptr;
  RawShapes shapes{};
  ~RawScene() {
    if (scene) rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

std::unique_ptr<RawScene> rawMeshScene(const MeshData &m) {
  auto raw = std::make_unique<RawScene>();
  raw->scene = rtcNewScene(raw->device);
  rtcSetSceneFlags(raw->scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(raw->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto *vb = static_cast<float *>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.positions.size()));
  std::copy_n(&m.positions[0].x, 3 * m.positions.size(), vb);
  auto *ib = static_cast<uint32_t *>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangles.size()));
  std::copy(m.triangleIndices.begin(), m.triangleIndices.end(), ib);
  rtcCommitGeometry(g);
  rtcAttachGeometry(raw->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(raw->scene);
  return raw;
}

std::unique_ptr<RawScene> rawShapeScene(const std::vector<Entity> &entities) {
  auto raw = std::make_unique<RawScene>();
  raw->shapes.entities = &entities;
  raw->scene = rtcNewScene(raw->device);
  rtcSetSceneFlags(raw->scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(raw->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(entities.size()));
  rtcSetGeometryUserData(g, &raw->shapes);
  rtcSetGeometryBoundsFunction(g, rawBounds, nullptr);
  rtcSetGeometryIntersectFunction(g, rawIntersect);
  rtcSetGeometryOccludedFunction(g, rawOccluded);
  rtcCommitGeometry(g);
  rtcAttachGeometry(raw->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(raw->scene);
  return raw;
}

size_t rawTrace1(RTCScene scene, const std::vector<Ray> &rays) {
  size_t hits = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (const Ray &r : rays) {
    RTCRayHit rh;
    rh.ray = {float(r.o.x), float(r.o.y), float(r.o.z), 0, float(r.d.x), float(r.d.y),
              float(r.d.z), 0, 1e30f, 0xFFFFFFFFu, 0, 0};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

size_t rawTrace8(RTCScene scene, const std::vector<Ray> &rays) {
  size_t hits = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (size_t base = 0; base < rays.size(); base += 8) {
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    for (int i = 0; i < 8; ++i) {
      size_t k = std::min(base + i, rays.size() - 1);
      valid[i] = base + i < rays.size() ? -1 : 0;
      const Ray &r = rays[k];
      rh.ray.org_x[i] = float(r.o.x), rh.ray.org_y[i] = float(r.o.y),
      rh.ray.org_z[i] = float(r.o.z);
      rh.ray.dir_x[i] = float(r.d.x), rh.ray.dir_y[i] = float(r.d.y),
      rh.ray.dir_z[i] = float(r.d.z);
      rh.ray.tnear[i] = 0, rh.ray.tfar[i] = 1e30f, rh.ray.time[i] = 0;
      rh.ray.mask[i] = 0xFFFFFFFFu, rh.ray.id[i] = 0, rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, scene, &ctx, &rh);
    for (int i = 0; i < 8; ++i) hits += valid[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

size_t lrayTrace1(const EmbreeAccelerator &a, const std::vector<Ray> &rays) {
  size_t hits = 0;
  Hit h;
  for (const Ray &r : rays) hits += a.intersect(r, h);
  return hits;
}

size_t lrayTraceCoherent(const EmbreeAccelerator &a, const std::vector<Ray> &rays) {
  constexpr size_t kBatch = kTileSize * kTileSize; // one tile, as the renderer traces it
  size_t hits = 0;
  Hit h[kBatch];
  uint8_t found[kBatch];
  for (size_t base = 0; base < rays.size(); base += kBatch) {
    size_t n = std::min(kBatch, rays.size() - base);
    a.intersectCoherent(rays.data() + base, n, h, found);
    for (size_t i = 0; i < n; ++i) hits += found[i];
  }
  return hits;
}

void compare(const char *name, RTCScene raw, const EmbreeAccelerator &accel,
             const std::vector<Ray> &rays) {
  constexpr int kRounds = 7;
  size_t h[4];
  const std::function<void()> loops[4] = {[&] { h[0] = rawTrace1(raw, rays); },
                                          [&] { h[1] = lrayTrace1(accel, rays); },
                                          [&] { h[2] = rawTrace8(raw, rays); },
                                          [&] { h[3] = lrayTraceCoherent(accel, rays); }};
  std::vector<double> t[4];
  for (int r = 0; r < kRounds; ++r)
    for (int k = 0; k < 4; ++k) {
      double a = threadSeconds();
      loops[k]();
      t[k].push_back(threadSeconds() - a);
    }
  double n = static_cast<double>(rays.size()) / 1e6;
  std::printf("%s: %zu rays, hits raw %zu / lray %zu\n", name, rays.size(), h[0], h[1]);
  // LRay / raw: the ratio of the medians, and the range of the rounds' ratios.
  auto report = [&](const char *line, int rawIdx) {
    std::vector<double> ratio;
    for (int r = 0; r < kRounds; ++r) ratio.push_back(t[rawIdx][r] / t[rawIdx + 1][r]);
    double tr = median(t[rawIdx]), tl = median(t[rawIdx + 1]);
    auto [lo, hi] = std::minmax_element(ratio.begin(), ratio.end());
    std::printf(line, n / tr, n / tl, 100 * tr / tl, 100 * *lo, 100 * *hi);
  };
  report("  single  raw rtcIntersect1 %7.2f Mrays/s   lray intersect         %7.2f Mrays/s  "
         "(%.0f%%, rounds %.0f-%.0f%%)\n",
         0);
  report("  packet  raw rtcIntersect8 %7.2f Mrays/s   lray intersectCoherent %7.2f Mrays/s  "
         "(%.0f%%, rounds %.0f-%.0f%%)\n",
         2);
}

int run(int w, int hgt) {
  // 1. ~1M-triangle mesh.
  auto terrain = makeTerrain(708);
  Scene meshScene;
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = terrain;
  e.smooth = true;
  meshScene.entities.push_back(e);
  EmbreeAccelerator meshAccel(meshScene);
  auto rawMesh = rawMeshScene(*terrain);
  AcceleratorStats ms = meshAccel.stats();
  std::printf("mesh: %zu triangles, build %.3f s, Embree memory %.1f bytes/triangle (+ MeshData "
              "%.1f bytes/triangle shared with Embree)\n",
              terrain->triangles.size(), ms.buildSeconds,
              double(ms.memoryBytes) / double(terrain->triangles.size()),
              double(terrain->memoryBytes()) / double(terrain->triangles.size()));
  compare("mesh", rawMesh->scene, meshAccel, cameraRays({0, 1.2, -1.8}, {0, 0, 0}, w, hgt));

  // 2. 1e5 analytic shapes.
  Scene shapes;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1), s(0.2, 0.8);
  for (int i = 0; i < 100000; ++i) {
    Entity x;
    x.shape = makeShape(static_cast<ShapeKind>(i % 4));
    x.worldFromObject = Transform::translate(Vec3(u(rng), u(rng), u(rng)) * 50) *
                        Transform::rotate({u(rng), u(rng), 1}, 180 * u(rng)) *
                        Transform::scale(s(rng), s(rng), s(rng));
    shapes.entities.push_back(x);
  }
  EmbreeAccelerator shapeAccel(shapes);
  auto rawShapes = rawShapeScene(shapes.entities);
  std::printf("shapes: %zu analytic, build %.3f s, memory %.1f bytes/shape\n",
              shapes.entities.size(), shapeAccel.stats().buildSeconds,
              double(shapeAccel.stats().memoryBytes) / double(shapes.entities.size()));
  compare("shapes", rawShapes->scene, shapeAccel, cameraRays({0, 0, -90}, {0, 0, 0}, w, hgt));

  // 3. Cost of an instance: 2 vs 1002 copies of the same mesh.
  auto small = makeTerrain(32);
  auto instanced = [&](int copies) {
    Scene sc;
    for (int i = 0; i < copies; ++i) {
      Entity c;
      c.shape = makeShape(ShapeKind::Mesh);
      c.mesh = small;
      c.worldFromObject = Transform::translate({3.0 * (i % 40), 0, 3.0 * (i / 40)});
      sc.entities.push_back(c);
    }
    EmbreeAccelerator a(sc);
    return a.stats();
  };
  AcceleratorStats one = instanced(2), many = instanced(1002);
  std::printf("instances: %zu-triangle mesh; each extra instance costs %.0f bytes and %.2f us of "
              "build (scene of 2 copies: %zu bytes)\n",
              small->triangles.size(), double(many.memoryBytes - one.memoryBytes) / 1000,
              1e6 * (many.buildSeconds - one.buildSeconds) / 1000, one.memoryBytes);
  return 0;
}

} // namespace
} // namespace lray

int main(int argc, char **argv) {
  int w = argc > 2 ? std::atoi(argv[1]) : 1024, h = argc > 2 ? std::atoi(argv[2]) : 768;
  return lray::run(w, h);
}
