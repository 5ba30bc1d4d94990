// CSG against an independent oracle: random nested trees of random solids,
// random rays (from outside and from inside), through both backends. The
// oracle knows nothing of spans or sweeps: it marches along the ray
// classifying points with each solid's own membership test (csg_test_trees.h),
// bisects each solid's transitions, and keeps the first transition that the
// operators above that solid keep, judged by classifying the other children
// at that point (POV-Ray's rules, written out again by recursion on the
// tree as written). The hit must match it: t, the solid, the side the
// normal faces, and occlusion just before and after it.
#include "render/backends.h"

#include "csg_test_trees.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace lray {
namespace {

using test::CsgSpec;
using test::insideSolid;
using test::leafSpec;
using test::opSpec;

/// The oracle's view of one tree: the spec, and the world-placed leaves in
/// the spec's depth-first order (as csgEntity adds them).
struct Oracle {
  const CsgSpec &spec;
  const CsgTree &tree;

  /// Inside `spec` at point p, given each leaf's membership.
  bool inside(const CsgSpec &s, const std::vector<bool> &in, uint32_t &next) const {
    if (!s.op) return in[next++];
    std::vector<bool> kids;
    for (const CsgSpec &c : s.children) kids.push_back(inside(c, in, next));
    switch (*s.op) {
    case CsgOp::Union:
    case CsgOp::Merge: return std::count(kids.begin(), kids.end(), true) > 0;
    case CsgOp::Intersection: return std::count(kids.begin(), kids.end(), false) == 0;
    case CsgOp::Difference:
      return kids[0] && std::count(kids.begin() + 1, kids.end(), true) == 0;
    }
    return false;
  }

  /// Whether a surface crossing of leaf `target` at a point with memberships
  /// `in` is kept; `inverted` collects how often it is subtracted. Returns
  /// -1 when the leaf is not below s.
  int kept(const CsgSpec &s, const std::vector<bool> &in, uint32_t target, uint32_t &next,
           bool &inverted) const {
    if (!s.op) return next++ == target ? 1 : -1;
    std::vector<bool> kids;
    int found = -1;
    size_t which = 0;
    for (size_t k = 0; k < s.children.size(); ++k) {
      uint32_t before = next;
      bool inv = false;
      int r = kept(s.children[k], in, target, next, inv);
      uint32_t after = before;
      kids.push_back(inside(s.children[k], in, after));
      if (r >= 0) {
        found = r;
        which = k;
        inverted = inv;
      }
    }
    if (found <= 0) return found;
    auto othersIn = [&](size_t from) {
      int n = 0;
      for (size_t k = from; k < kids.size(); ++k) n += k != which && kids[k];
      return n;
    };
    switch (*s.op) {
    case CsgOp::Union: return 1;
    case CsgOp::Merge: return othersIn(0) == 0;
    case CsgOp::Intersection: return othersIn(0) == int(kids.size()) - 1;
    case CsgOp::Difference:
      if (which == 0) return othersIn(1) == 0;
      inverted = !inverted;
      return kids[0] && othersIn(1) == 0;
    }
    return 0;
  }

  std::vector<bool> memberships(const Vec3 &p) const {
    std::vector<bool> in;
    for (const CsgTree::Leaf &l : tree.leaves) in.push_back(insideSolid(l.entity, p));
    return in;
  }

  struct Expected {
    bool hit = false;
    bool ambiguous = false;
    double t = 0;
    uint32_t leaf = 0;
    bool normalAlongRay = false;
  };

  /// The first kept transition in (tMin, tEnd), marching `steps` samples.
  Expected run(const Ray &ray, double tEnd, int steps) const {
    struct Transition {
      double t;
      uint32_t leaf;
      bool entering;
    };
    std::vector<Transition> found;
    const double t0 = ray.tMin, dt = (tEnd - t0) / steps;
    std::vector<bool> prev = memberships(ray.at(t0));
    for (int i = 1; i <= steps; ++i) {
      const double t = t0 + dt * i;
      std::vector<bool> now = memberships(ray.at(t));
      for (uint32_t l = 0; l < now.size(); ++l) {
        if (now[l] == prev[l]) continue;
        double a = t - dt, b = t; // bisect leaf l's membership
        for (int k = 0; k < 80; ++k) {
          double m = 0.5 * (a + b);
          if (insideSolid(tree.leaves[l].entity, ray.at(m)) == bool(prev[l])) a = m;
          else b = m;
        }
        found.push_back({0.5 * (a + b), l, bool(now[l])});
      }
      prev = std::move(now);
    }
    std::sort(found.begin(), found.end(), [](auto &x, auto &y) { return x.t < y.t; });
    Expected e;
    const double scale = std::max(1.0, std::fabs(tEnd));
    for (size_t i = 0; i < found.size(); ++i) {
      const Transition &x = found[i];
      // Coincident or near-tangent transitions, or one at the ray's start:
      // the oracle's own resolution decides, not the geometry.
      bool close = (i > 0 && x.t - found[i - 1].t < 1e-7 * scale) ||
                   (i + 1 < found.size() && found[i + 1].t - x.t < 1e-7 * scale) ||
                   x.t - ray.tMin < 1e-7 * scale;
      // The other leaves at the point: x's own leaf is judged as crossing.
      std::vector<bool> in = memberships(ray.at(x.t));
      uint32_t next = 0;
      bool inverted = false;
      int k = kept(spec, in, x.leaf, next, inverted);
      if (k == 1) {
        e.ambiguous = close;
        e.hit = true;
        e.t = x.t;
        e.leaf = x.leaf;
        e.normalAlongRay = x.entering == inverted; // leaving the leaf, or entering a hole
        return e;
      }
      if (close) {
        e.ambiguous = true;
        return e;
      }
    }
    return e;
  }
};

Transform randomPlacement(std::mt19937_64 &rng) {
  std::uniform_real_distribution<double> u(-1, 1), s(0.35, 1.1);
  return Transform::translate({0.7 * u(rng), 0.7 * u(rng), 0.7 * u(rng)}) *
         Transform::rotate({u(rng), u(rng), u(rng) + 1.5}, 180 * u(rng)) *
         Transform::scale(s(rng), s(rng), s(rng));
}

CsgSpec randomTree(std::mt19937_64 &rng, int depth, bool &hasPlane) {
  std::uniform_int_distribution<int> op(0, 3), kids(2, 3), kind(0, 9);
  std::vector<CsgSpec> children;
  const int n = kids(rng);
  for (int i = 0; i < n; ++i) {
    if (depth < 2 && kind(rng) < 3) {
      children.push_back(randomTree(rng, depth + 1, hasPlane));
      continue;
    }
    const ShapeKind kinds[] = {ShapeKind::Sphere, ShapeKind::Cube,   ShapeKind::Cylinder,
                               ShapeKind::Cone,   ShapeKind::Torus,  ShapeKind::Sphere,
                               ShapeKind::Cube,   ShapeKind::Cylinder, ShapeKind::Torus,
                               ShapeKind::Plane};
    ShapeKind k = kinds[kind(rng)];
    CsgSpec leaf = leafSpec(k, randomPlacement(rng));
    if (k == ShapeKind::Torus)
      std::get<Torus>(leaf.leaf.shape).minor = 0.2 + 0.3 * (kind(rng) / 9.0);
    hasPlane = hasPlane || k == ShapeKind::Plane;
    children.push_back(std::move(leaf));
  }
  return opSpec(static_cast<CsgOp>(op(rng)), std::move(children));
}

TEST(CsgOracle, RandomTreesMatchPointClassificationOnBothBackends) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr int kTrees = 250, kRaysPerTree = 200; // 50,000 rays, each on both backends
  long compared = 0, hits = 0, ambiguous = 0, inside = 0, refined = 0;
  for (int tree = 0; tree < kTrees; ++tree) {
    bool hasPlane = false;
    CsgSpec spec = randomTree(rng, 0, hasPlane);
    // Planes make a tree unbounded: clip it to a ball for the march.
    if (hasPlane)
      spec =
          opSpec(CsgOp::Intersection,
                 {leafSpec(ShapeKind::Sphere, Transform::scale(2.5, 2.5, 2.5)), std::move(spec)});
    spec.transform = Transform::translate({u(rng), u(rng), u(rng)});
    Scene scene;
    scene.entities.push_back(test::csgEntity(spec));
    scene.textures.push_back({});
    const CsgTree &csgTree = *std::get<Csg>(scene.entities[0].shape).tree;
    // The oracle works on the tree as written, translated as the entity is.
    CsgSpec placed = spec;
    Oracle oracle{placed, csgTree};
    auto embree = makeAccelerator(BackendKind::Embree, scene);
    auto kdtree = makeAccelerator(BackendKind::KdTree, scene);
    for (int i = 0; i < kRaysPerTree; ++i) {
      const Vec3 centre = spec.transform.applyPoint({0, 0, 0});
      Ray ray;
      if (i % 4 == 3) { // from inside the region, any direction
        ray.o = centre + Vec3{u(rng), u(rng), u(rng)};
        ray.d = Vec3{u(rng), u(rng), u(rng)} * 1.7;
        ++inside;
      } else {
        Vec3 dir = normalize(Vec3{u(rng), u(rng), u(rng)});
        ray.o = centre + dir * 5;
        ray.d = (centre + Vec3{u(rng), u(rng), u(rng)} - ray.o) * 0.6;
      }
      ray.tMin = 0;
      if (!(length(ray.d) > 0.1)) continue;
      const double tEnd = 12 / length(ray.d); // past the region (radius < 4.5)
      Oracle::Expected e = oracle.run(ray, tEnd, 1000);
      for (const auto *accel : {embree.get(), kdtree.get()}) {
        Hit h;
        bool hit = accel->intersect(ray, h);
        if (e.ambiguous) {
          ++ambiguous;
          continue;
        }
        bool agrees = hit == e.hit &&
                      (!hit || (std::fabs(h.t - e.t) <= 1e-6 * (1 + e.t) && h.primitive == e.leaf));
        if (!agrees) {
          // A solid crossed for less than one step is invisible to the
          // coarse march: ask again with 200x finer steps.
          Oracle::Expected fine = oracle.run(ray, tEnd, 200000);
          if (fine.ambiguous) {
            ++ambiguous;
            continue;
          }
          e = fine;
          ++refined;
        }
        ++compared;
        ASSERT_EQ(hit, e.hit) << "tree " << tree << " ray " << i << " t " << e.t;
        if (!hit) continue;
        ++hits;
        ASSERT_NEAR(h.t, e.t, 1e-6 * (1 + e.t)) << "tree " << tree << " ray " << i;
        ASSERT_EQ(h.primitive, e.leaf) << "tree " << tree << " ray " << i;
        ASSERT_EQ(dot(h.ng, ray.d) > 0, e.normalAlongRay) << "tree " << tree << " ray " << i;
        Ray before = ray, after = ray;
        before.tMax = e.t * (1 - 1e-6);
        after.tMax = e.t * (1 + 1e-6);
        ASSERT_FALSE(accel->occluded(before)) << "tree " << tree << " ray " << i;
        ASSERT_TRUE(accel->occluded(after)) << "tree " << tree << " ray " << i;
      }
    }
  }
  // Enough real comparisons, few set aside.
  EXPECT_GE(compared, 95000);
  EXPECT_GT(hits, 20000);
  EXPECT_LT(ambiguous, compared / 100);
  EXPECT_GT(inside, 10000);
  std::printf("compared %ld (hits %ld, from inside %ld), ambiguous %ld, refined %ld\n", compared,
              hits, inside, ambiguous, refined);
}

} // namespace
} // namespace lray
