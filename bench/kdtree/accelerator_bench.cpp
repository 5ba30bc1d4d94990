// Benchmarks: see accelerator_bench.h.
#include "bench/kdtree/accelerator_bench.h"

#include "run/render_stats.h"

#include "render/camera_rays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <cmath>
#include <numbers>
#include <vector>

namespace lray::bench {

namespace {

// CPU time of the process (all threads) and of the calling thread: robust
// figures on a machine shared with other work.
double cpuSeconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

} // namespace

AcceleratorFigures measureAccelerator(const Scene &scene, const AcceleratorFactory &make,
                                      int width, int height) {
  AcceleratorFigures fig;
  auto start = std::chrono::steady_clock::now();
  double cpuStart = cpuSeconds(CLOCK_PROCESS_CPUTIME_ID);
  std::unique_ptr<Accelerator> accel = make(scene);
  fig.wallBuildSeconds = secondsSince(start);
  fig.cpuBuildSeconds = cpuSeconds(CLOCK_PROCESS_CPUTIME_ID) - cpuStart;
  fig.stats = accel->stats();

  CameraRays camera(scene.camera, width, height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) rays.push_back(camera.generate(x + 0.5, y + 0.5));
  fig.rays = rays.size();

  size_t hits = 0;
  start = std::chrono::steady_clock::now();
  double threadStart = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
  for (const Ray &ray : rays) {
    Hit hit;
    hits += accel->intersect(ray, hit);
  }
  fig.raysPerSecondOneThread = static_cast<double>(rays.size()) / secondsSince(start);
  fig.raysPerCpuSecond =
      static_cast<double>(rays.size()) / (cpuSeconds(CLOCK_THREAD_CPUTIME_ID) - threadStart);
  fig.hitFraction = static_cast<double>(hits) / static_cast<double>(rays.size());

  std::atomic<size_t> parallelHits{0};
  start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024),
                    [&](const tbb::blocked_range<size_t> &range) {
                      size_t local = 0;
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        Hit hit;
                        local += accel->intersect(rays[i], hit);
                      }
                      parallelHits.fetch_add(local, std::memory_order_relaxed);
                    });
  fig.raysPerSecondAllThreads = static_cast<double>(rays.size()) / secondsSince(start);

  size_t blocked = 0;
  start = std::chrono::steady_clock::now();
  for (const Ray &ray : rays) blocked += accel->occluded(ray);
  fig.occludedPerSecondOneThread = static_cast<double>(rays.size()) / secondsSince(start);
  if (blocked != hits || parallelHits.load() != hits) fig.hitFraction = -1; // inconsistent backend
  return fig;
}

Scene makeBumpySphereScene(size_t triangles) {
  // A latitude/longitude grid with single-vertex poles: 2 (rings - 1) segments
  // triangles; segments = 2 rings.
  int rings = std::max(4, static_cast<int>(std::sqrt(static_cast<double>(triangles) / 4)));
  int segments = 2 * rings;
  auto mesh = std::make_shared<MeshData>();
  auto addVertex = [&](double theta, double phi) {
    double r = 1 + 0.05 * std::sin(7 * theta) * std::cos(11 * phi) +
               0.02 * std::sin(31 * theta + 5 * phi);
    Vec3 p = Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                  std::sin(theta) * std::sin(phi)) * r;
    mesh->positions.push_back(toVec3f(p));
  };
  addVertex(0, 0);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
      addVertex(std::numbers::pi * i / rings, 2 * std::numbers::pi * j / segments);
  addVertex(std::numbers::pi, 0);
  const uint32_t south = static_cast<uint32_t>(mesh->positions.size() - 1);
  auto ring = [&](int i, int j) {
    return static_cast<uint32_t>(1 + (i - 1) * segments + j % segments);
  };
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    MeshTriangle t;
    t.v[0] = a;
    t.v[1] = b;
    t.v[2] = c;
    mesh->triangles.push_back(t);
    mesh->triangleIndices.insert(mesh->triangleIndices.end(), {a, b, c});
  };
  for (int j = 0; j < segments; ++j) add(0, ring(1, j + 1), ring(1, j));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      add(ring(i, j), ring(i, j + 1), ring(i + 1, j));
      add(ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j));
    }
  for (int j = 0; j < segments; ++j) add(south, ring(rings - 1, j), ring(rings - 1, j + 1));
  // Flat-shaded: one normal per vertex direction is enough for a benchmark.
  for (const Vec3f &p : mesh->positions) {
    mesh->normals.push_back(toVec3f(normalize(Vec3(p.x, p.y, p.z))));
  }
  for (MeshTriangle &t : mesh->triangles)
    for (int k = 0; k < 3; ++k) t.n[k] = static_cast<int32_t>(t.v[k]);
  mesh->hasNormals = true;

  Scene scene;
  Entity e;
  e.shape = makeShape(ShapeKind::Mesh);
  e.mesh = mesh;
  scene.entities.push_back(e);
  scene.textures.emplace_back();
  scene.pigments.emplace_back();
  scene.camera.fov = 45;
  scene.camera.aspect = 4.0 / 3.0;
  scene.camera.worldFromCamera = Transform::translate({0, 0, -3});
  return scene;
}

} // namespace lray::bench
