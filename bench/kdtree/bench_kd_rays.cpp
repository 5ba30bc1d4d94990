// Benchmarks: kd-tree against Embree on bench/backends' triangle ray sets
// (bumpy sphere mesh, 320x240 camera rays one at a time, shadow rays to a
// light, secondary rays in random directions from the primary hits), timed
// in thread CPU time, each figure the median of several passes, both
// backends interleaved in one process: the ratios hold on a busy machine.
// Also prints a digest of the kd-tree's results (hits and occlusion flags),
// so a traversal change can be checked for bit-identical output. Usage:
//   bench_kd_rays [maxN=1000000] [repeats=5] [minN=100]
#include "render/backends.h"
#include "bench/kdtree/accelerator_bench.h"
#include "math/spawn.h"
#include "math/random.h"
#include "render/camera_rays.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <vector>

using namespace lray;

namespace {

double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// FNV-1a over the bits that must not change.
struct Digest {
  uint64_t h = 1469598103934665603ull;
  void add(uint64_t x) {
    for (int i = 0; i < 8; ++i) h = (h ^ ((x >> (8 * i)) & 0xff)) * 1099511628211ull;
  }
  void add(double d) { add(std::bit_cast<uint64_t>(d)); }
  void add(const Hit &hit) {
    add(uint64_t{hit.entity} << 32 | hit.primitive);
    add(hit.t);
    add(hit.u);
    add(hit.v);
    add(hit.p.x);
    add(hit.p.y);
    add(hit.p.z);
  }
};

struct RaySets {
  std::vector<Ray> primary, shadow, secondary;
};

// The ray sets of bench/backends, built from Embree's hits.
RaySets makeRays(const Scene &scene, const Accelerator &embree) {
  RaySets s;
  const int width = 320, height = 240;
  CameraRays camera(scene.camera, width, height);
  for (int by = 0; by < height; by += 8)
    for (int bx = 0; bx < width; bx += 8)
      for (int y = by; y < std::min(by + 8, height); ++y)
        for (int x = bx; x < std::min(bx + 8, width); ++x)
          s.primary.push_back(camera.generate(x + 0.5, y + 0.5));
  Vec3 light{-30, 40, -30};
  Sampler rng(1, 2, 3);
  for (const Ray &r : s.primary) {
    Hit hit;
    if (!embree.intersect(r, hit)) continue;
    s.shadow.push_back(spawnRayTo(hit, light));
    Vec3 d;
    do d = Vec3{rng.next() * 2 - 1, rng.next() * 2 - 1, rng.next() * 2 - 1};
    while (dot(d, d) > 1 || dot(d, d) < 1e-6);
    if (dot(d, hit.ng) < 0) d = -d;
    s.secondary.push_back(spawnRay(hit, d));
  }
  return s;
}

// Seconds of thread CPU time per ray for one pass over `rays`.
double passIntersect(const Accelerator &a, const std::vector<Ray> &rays, Digest *digest) {
  Hit hit;
  size_t n = 0;
  double t0 = threadSeconds();
  for (const Ray &r : rays) {
    bool found = a.intersect(r, hit);
    n += found;
    if (digest) {
      digest->add(uint64_t{found});
      if (found) digest->add(hit);
    }
  }
  double t = threadSeconds() - t0;
  if (n == size_t(-1)) std::puts("");
  return t / static_cast<double>(rays.size());
}

double passOccluded(const Accelerator &a, const std::vector<Ray> &rays, Digest *digest) {
  size_t n = 0;
  double t0 = threadSeconds();
  for (const Ray &r : rays) {
    bool blocked = a.occluded(r);
    n += blocked;
    if (digest) digest->add(uint64_t{blocked});
  }
  double t = threadSeconds() - t0;
  if (n == size_t(-1)) std::puts("");
  return t / static_cast<double>(rays.size());
}

} // namespace

int main(int argc, char **argv) {
  size_t maxN = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  size_t minN = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 100;
  double load[3] = {0, 0, 0};
  getloadavg(load, 3);
  std::printf("load average %.2f %.2f %.2f; ns per ray (median of %d), ratio = embree/kd time\n",
              load[0], load[1], load[2], repeats);
  std::printf("%8s | %9s %9s %5s | %9s %9s %5s | %9s %9s %5s\n", "N", "prim emb", "prim kd",
              "ratio", "shad emb", "shad kd", "ratio", "sec emb", "sec kd", "ratio");
  Digest all;
  for (size_t n = minN; n <= maxN; n *= 10) {
    Scene scene = bench::makeBumpySphereScene(n);
    auto embree = makeAccelerator(BackendKind::Embree, scene);
    auto kd = makeAccelerator(BackendKind::KdTree, scene);
    RaySets rays = makeRays(scene, *embree);
    Digest digest;
    passIntersect(*kd, rays.primary, &digest);
    passOccluded(*kd, rays.shadow, &digest);
    passIntersect(*kd, rays.secondary, &digest);
    all.add(digest.h);
    std::vector<double> t[6];
    for (int r = 0; r < repeats; ++r) {
      t[0].push_back(passIntersect(*embree, rays.primary, nullptr));
      t[1].push_back(passIntersect(*kd, rays.primary, nullptr));
      t[2].push_back(passOccluded(*embree, rays.shadow, nullptr));
      t[3].push_back(passOccluded(*kd, rays.shadow, nullptr));
      t[4].push_back(passIntersect(*embree, rays.secondary, nullptr));
      t[5].push_back(passIntersect(*kd, rays.secondary, nullptr));
    }
    double m[6];
    for (int i = 0; i < 6; ++i) m[i] = median(t[i]) * 1e9;
    std::printf("%8zu | %9.1f %9.1f %5.2f | %9.1f %9.1f %5.2f | %9.1f %9.1f %5.2f"
                "  digest %016llx\n",
                n, m[0], m[1], m[0] / m[1], m[2], m[3], m[2] / m[3], m[4], m[5], m[4] / m[5],
                static_cast<unsigned long long>(digest.h));
    std::fflush(stdout);
  }
  std::printf("digest of all %016llx\n", static_cast<unsigned long long>(all.h));
  return 0;
}
