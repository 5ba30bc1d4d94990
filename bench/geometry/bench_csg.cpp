// Benchmark for CSG (geometry/csg_ray.cpp, issue 20): rays per second
// through a grid of CSG objects against the same solids added as plain
// shapes, on both backends. Three kinds of object: the classic
// Difference { Intersection { Cube, Sphere }, three rods } (5 solids), a
// lens Intersection { Sphere, Sphere } (2) and a Merge of two spheres (2).
// Closest-hit camera rays and shadow rays (occluded) towards a light from
// the hit points. Single thread; medians of five rounds of thread CPU time,
// the CSG and plain scenes timed one after the other in each round.
//
//   bench_csg [width height]     (default 640 x 480 rays per view)
#include "render/backends.h"
#include "geometry/csg_tree.h"
#include "geometry/shape.h"
#include "math/spawn.h"
#include "render/camera_rays.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

namespace lray {
namespace {

double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Entity solid(ShapeKind kind, const Transform &xf) {
  Entity e;
  e.shape = makeShape(kind);
  e.worldFromObject = xf;
  return e;
}

struct Object {
  CsgOp root;
  std::vector<std::pair<int, Entity>> leaves; ///< (parent node, solid), nodes made in order
  std::vector<std::pair<CsgOp, int>> nodes;   ///< (operator, parent) after the root
};

Object classic(const Transform &at) {
  const Transform rod = Transform::scale(0.4, 3, 0.4) * Transform::translate({0, -0.5, 0});
  Object o{CsgOp::Difference, {}, {{CsgOp::Intersection, 0}}};
  o.leaves = {{1, solid(ShapeKind::Cube, at)},
              {1, solid(ShapeKind::Sphere, at * Transform::scale(0.68, 0.68, 0.68))},
              {0, solid(ShapeKind::Cylinder, at * rod)},
              {0, solid(ShapeKind::Cylinder, at * Transform::rotate({1, 0, 0}, 90) * rod)},
              {0, solid(ShapeKind::Cylinder, at * Transform::rotate({0, 0, 1}, 90) * rod)}};
  return o;
}

Object lens(const Transform &at) {
  return {CsgOp::Intersection,
          {{0, solid(ShapeKind::Sphere,
                     at * Transform::translate({-0.3, 0, 0}) * Transform::scale(0.5, 0.5, 0.5))},
           {0, solid(ShapeKind::Sphere,
                     at * Transform::translate({0.3, 0, 0}) * Transform::scale(0.5, 0.5, 0.5))}},
          {}};
}

Object merged(const Transform &at) {
  return {CsgOp::Merge,
          {{0, solid(ShapeKind::Sphere,
                     at * Transform::translate({-0.2, 0, 0}) * Transform::scale(0.4, 0.4, 0.4))},
           {0, solid(ShapeKind::Sphere,
                     at * Transform::translate({0.2, 0, 0}) * Transform::scale(0.4, 0.4, 0.4))}},
          {}};
}

Entity csgOf(const Object &o) {
  auto tree = std::make_shared<CsgTree>();
  tree->addNode(o.root, CsgTree::kNoParent);
  for (const auto &[op, parent] : o.nodes) tree->addNode(op, static_cast<uint32_t>(parent));
  for (const auto &[parent, e] : o.leaves) tree->addLeaf(e, static_cast<uint32_t>(parent));
  tree->finish();
  Entity e;
  e.shape = Csg{std::move(tree)};
  return e;
}

/// An n x n grid of objects of one kind, as CSG entities or as plain solids.
Scene grid(Object (*make)(const Transform &), int n, bool asCsg) {
  Scene s;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Object o =
          make(Transform::translate({1.3 * (i - 0.5 * (n - 1)), 1.3 * (j - 0.5 * (n - 1)), 0}) *
               Transform::rotate({1, 1, 0.3}, 37.0 * (i + 2 * j)));
      if (asCsg) s.entities.push_back(csgOf(o));
      else
        for (const auto &leaf : o.leaves) s.entities.push_back(leaf.second);
    }
  s.textures.push_back({});
  s.camera.fov = 50;
  s.camera.aspect = 4.0 / 3;
  s.camera.worldFromCamera = Transform::lookAt({0, 0, -1.25 * n - 2}, {0, 0, 0}, {0, 1, 0});
  return s;
}

struct Rates {
  double primary, shadow; ///< million rays per second
  double hitFraction;
};

Rates measure(const Accelerator &accel, const std::vector<Ray> &rays, const Vec3 &light,
              double &primarySeconds, double &shadowSeconds) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> found(rays.size());
  double t0 = threadSeconds();
  for (size_t i = 0; i < rays.size(); ++i) found[i] = accel.intersect(rays[i], hits[i]);
  double t1 = threadSeconds();
  size_t shadowRays = 0, blocked = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!found[i]) continue;
    ++shadowRays;
    blocked += accel.occluded(spawnRayTo(hits[i], light));
  }
  double t2 = threadSeconds();
  primarySeconds = t1 - t0;
  shadowSeconds = t2 - t1;
  Rates r;
  r.primary = double(rays.size()) / primarySeconds * 1e-6;
  r.shadow = double(shadowRays) / std::max(shadowSeconds, 1e-9) * 1e-6;
  r.hitFraction = double(shadowRays) / double(rays.size());
  (void)blocked;
  return r;
}

int run(int width, int height) {
  struct Kind {
    const char *name;
    Object (*make)(const Transform &);
    int solids;
  };
  const Kind kinds[] = {
      {"classic (5 solids)", classic, 5}, {"lens (2)", lens, 2}, {"merge (2)", merged, 2}};
  const int n = 8;
  std::printf(
      "%dx%d camera rays + shadow rays from the hits, %dx%d objects, 1 thread, medians of 5\n",
      width, height, n, n);
  std::printf("%-20s %-7s %13s %13s %13s %13s %9s %9s\n", "object", "backend", "csg Mray/s",
              "plain Mray/s", "csg shadow", "plain shadow", "ratio", "shadow");
  for (const Kind &k : kinds) {
    Scene csg = grid(k.make, n, true), plain = grid(k.make, n, false);
    CameraRays cam(csg.camera, width, height);
    std::vector<Ray> rays;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) rays.push_back(cam.generate(x + 0.5, y + 0.5));
    const Vec3 light{-20, 30, -40};
    for (BackendKind backend : {BackendKind::Embree, BackendKind::KdTree}) {
      auto a = makeAccelerator(backend, csg), b = makeAccelerator(backend, plain);
      std::vector<double> cp, cs, pp, ps;
      for (int round = 0; round < 5; ++round) {
        double p, s;
        measure(*a, rays, light, p, s);
        cp.push_back(p);
        cs.push_back(s);
        measure(*b, rays, light, p, s);
        pp.push_back(p);
        ps.push_back(s);
      }
      double dummyP, dummyS;
      Rates rc = measure(*a, rays, light, dummyP, dummyS);
      Rates rp = measure(*b, rays, light, dummyP, dummyS);
      const double csgP = rays.size() / median(cp) * 1e-6, plainP = rays.size() / median(pp) * 1e-6;
      const double csgS = rc.hitFraction * rays.size() / median(cs) * 1e-6;
      const double plainS = rp.hitFraction * rays.size() / median(ps) * 1e-6;
      std::printf("%-20s %-7s %13.2f %13.2f %13.2f %13.2f %9.2f %9.2f\n", k.name,
                  backendName(backend).c_str(), csgP, plainP, csgS, plainS, plainP / csgP,
                  plainS / csgS);
    }
  }
  std::printf("ratio: plain rays/s over CSG rays/s (time per CSG ray / time per plain ray)\n");
  return 0;
}

} // namespace
} // namespace lray

int main(int argc, char **argv) {
  int w = argc > 2 ? std::atoi(argv[1]) : 640, h = argc > 2 ? std::atoi(argv[2]) : 480;
  return lray::run(w, h);
}
