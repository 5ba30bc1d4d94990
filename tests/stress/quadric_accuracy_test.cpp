// Robustness suite (issue 8): accuracy of the quadrics' (and the torus')
// ray parameter at a distance of 1e4 under a non-uniform scale and a
// rotation, against an independent long-double reference, through both
// backends.
#include "long_double_root.h"
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace lray::stress {
namespace {

using LD = long double;

struct V3 {
  LD x, y, z;
};

V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 mul(V3 a, LD s) { return {a.x * s, a.y * s, a.z * s}; }
LD dotL(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// The shape's surface defined by the stored (double) worldFromObject
/// matrix, intersected in long double: the world ray goes into object
/// space through the matrix inverted in long double, is re-origined at its
/// closest approach to the shape (so the quadric constant does not cancel)
/// and the object-space quadric is solved with the textbook formula.
class ReferenceShape {
public:
  ReferenceShape(ShapeKind kind, const Transform &xf) : kind_(kind) {
    const auto &m = xf.matrix().m;
    LD a[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) a[i][j] = m[i][j];
      t_[i] = m[i][3];
    }
    LD det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
        inv_[i][j] = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / det;
      }
  }

  /// Closest t > 0 in world-ray units; false on a miss.
  bool intersect(const Ray &r, LD &tOut) const {
    V3 rel{LD(r.o.x) - t_[0], LD(r.o.y) - t_[1], LD(r.o.z) - t_[2]};
    V3 o = apply(rel), d = apply({r.d.x, r.d.y, r.d.z});
    V3 centre{0, kind_ == ShapeKind::Sphere || kind_ == ShapeKind::Torus ? LD(0) : LD(0.5), 0};
    LD shift = dotL(add(centre, mul(o, -1)), d) / dotL(d, d);
    V3 os = add(o, mul(d, shift));
    LD best = INFINITY;
    auto consider = [&](LD t, bool ok) {
      if (ok && t + shift > 0 && t < best) best = t;
    };
    auto roots = [&](LD a, LD b, LD c, LD &t0, LD &t1) {
      LD disc = b * b - a * c;
      if (disc < 0 || a == 0) return false;
      LD s = std::sqrt(disc);
      t0 = (-b - s) / a;
      t1 = (-b + s) / a;
      return true;
    };
    LD t0, t1;
    switch (kind_) {
    case ShapeKind::Sphere:
      if (roots(dotL(d, d), dotL(os, d), dotL(os, os) - 1, t0, t1)) {
        consider(t0, true);
        consider(t1, true);
      }
      break;
    case ShapeKind::Cylinder:
      if (roots(d.x * d.x + d.z * d.z, os.x * d.x + os.z * d.z, os.x * os.x + os.z * os.z - 1, t0,
                t1))
        for (LD t : {t0, t1}) {
          LD y = os.y + t * d.y;
          consider(t, y >= 0 && y <= 1);
        }
      for (LD capY : {LD(0), LD(1)}) {
        if (d.y == 0) break;
        LD t = (capY - os.y) / d.y;
        LD x = os.x + t * d.x, z = os.z + t * d.z;
        consider(t, x * x + z * z <= 1);
      }
      break;
    case ShapeKind::Cone: {
      LD k = 1 - os.y;
      if (roots(d.x * d.x + d.z * d.z - d.y * d.y, os.x * d.x + os.z * d.z + k * d.y,
                os.x * os.x + os.z * os.z - k * k, t0, t1))
        for (LD t : {t0, t1}) {
          LD y = os.y + t * d.y;
          consider(t, y >= 0 && y <= 1);
        }
      if (d.y != 0) {
        LD t = -os.y / d.y;
        LD x = os.x + t * d.x, z = os.z + t * d.z;
        consider(t, x * x + z * z <= 1);
      }
      break;
    }
    case ShapeKind::Torus: {
      // h = (rho - R)^2 + y^2 - r^2 sampled along the bounding sphere's
      // chord, each sign change bisected to long double precision.
      const LD R = 1, rm = 0.25;
      auto h = [&](LD t) {
        V3 p = add(os, mul(d, t));
        LD a = std::sqrt(p.x * p.x + p.z * p.z) - R;
        return a * a + p.y * p.y - rm * rm;
      };
      LD dd = dotL(d, d), od = dotL(os, d);
      LD disc = od * od - dd * (dotL(os, os) - (R + rm) * (R + rm));
      if (disc <= 0) break;
      LD lo = (-od - std::sqrt(disc)) / dd, hi = (-od + std::sqrt(disc)) / dd;
      const int n = 500;
      auto bisect = [&](LD a, LD b) { return testing::bisectRoot(h, a, b); };
      LD step = (hi - lo) / n, prevH = h(lo), midH = h(lo + step);
      for (int i = 1; i <= n; ++i) {
        LD t = lo + step * i, ht = midH;
        if ((ht < 0) != (prevH < 0)) consider(bisect(t - step, t), true);
        LD nextH = i < n ? h(t + step) : ht;
        // A grazing chord shorter than a step: h dips below zero between
        // samples around a sampled local minimum; find the minimum.
        if (i < n && ht > 0 && ht <= prevH && ht <= nextH) {
          LD a = t - step, b = t + step;
          for (int k = 0; k < 160; ++k) {
            LD m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
            if (h(m1) < h(m2)) b = m2;
            else a = m1;
          }
          LD tMin = (a + b) / 2;
          if (h(tMin) < 0) consider(bisect(t - step, tMin), true);
        }
        prevH = ht;
        midH = nextH;
      }
      break;
    }
    default: return false;
    }
    if (!(best < INFINITY)) return false;
    tOut = best + shift;
    return true;
  }

private:
  V3 apply(V3 v) const {
    return {inv_[0][0] * v.x + inv_[0][1] * v.y + inv_[0][2] * v.z,
            inv_[1][0] * v.x + inv_[1][1] * v.y + inv_[1][2] * v.z,
            inv_[2][0] * v.x + inv_[2][1] * v.y + inv_[2][2] * v.z};
  }
  ShapeKind kind_;
  LD inv_[3][3];
  LD t_[3];
};

/// A random point on the shape's object-space surface (caps included).
Vec3 surfacePoint(ShapeKind kind, std::mt19937_64 &rng) {
  std::uniform_real_distribution<double> u(0, 1);
  double a = 2 * 3.14159265358979323846 * u(rng);
  switch (kind) {
  case ShapeKind::Sphere: {
    double y = 2 * u(rng) - 1, r = std::sqrt(1 - y * y);
    return {r * std::cos(a), y, r * std::sin(a)};
  }
  case ShapeKind::Cylinder: {
    double pick = u(rng);
    if (pick < 0.6) return {std::cos(a), u(rng), std::sin(a)};
    double r = std::sqrt(u(rng));
    return {r * std::cos(a), pick < 0.8 ? 0.0 : 1.0, r * std::sin(a)};
  }
  case ShapeKind::Torus: { // major 1, minor 0.25
    double b = 2 * 3.14159265358979323846 * u(rng), rho = 1 + 0.25 * std::cos(b);
    return {rho * std::cos(a), 0.25 * std::sin(b), rho * std::sin(a)};
  }
  default: { // cone
    if (u(rng) < 0.7) {
      double y = u(rng);
      return {(1 - y) * std::cos(a), y, (1 - y) * std::sin(a)};
    }
    double r = std::sqrt(u(rng));
    return {r * std::cos(a), 0, r * std::sin(a)};
  }
  }
}

class StressQuadricAccuracy : public ::testing::TestWithParam<BackendKind> {};

TEST_P(StressQuadricAccuracy, FarNonUniformlyScaledQuadricsWithinEightUlps) {
  const double ulp = 0x1p-52;
  const int raysPerCase = 20000;
  struct Placement {
    const char *name;
    Vec3 shapeAt;  ///< translation of the shape
    Vec3 originAt; ///< centre of the ray origins
  };
  const Placement placements[] = {
      {"shape at 1e4", {6000, 5000, 6000}, {0, 0, 0}},
      {"origin at 1e4", {0.5, -0.25, 0.125}, {-6000, 5000, -6000}},
  };
  double worstAll = 0;
  for (ShapeKind kind :
       {ShapeKind::Sphere, ShapeKind::Cylinder, ShapeKind::Cone, ShapeKind::Torus}) {
    for (const Placement &pl : placements) {
      Transform xf = Transform::translate(pl.shapeAt) * Transform::rotate({1, 2, 3}, 37) *
                     Transform::scale(3, 0.7, 1.9);
      Scene s;
      s.entities.push_back(shapeEntity(kind, xf));
      addDefaultMaterials(s);
      auto accel = makeAccelerator(GetParam(), s);
      ReferenceShape ref(kind, xf);
      std::mt19937_64 rng(42 + static_cast<int>(kind));
      std::uniform_real_distribution<double> jitter(-1, 1);
      double worst = 0, worstSteep = 0, worstHalf = 0, worstScaled = 0;
      int missMismatch = 0, hits = 0;
      for (int i = 0; i < raysPerCase; ++i) {
        Vec3 o = pl.originAt + Vec3(jitter(rng), jitter(rng), jitter(rng));
        Vec3 target = xf.applyPoint(surfacePoint(kind, rng));
        Ray r{o, normalize(target - o)};
        LD tRef = 0;
        bool refHit = ref.intersect(r, tRef);
        Hit h;
        bool hit = accel->intersect(r, h);
        if (hit != refHit) {
          ++missMismatch;
          continue;
        }
        if (!hit) continue;
        ++hits;
        double err = static_cast<double>(std::fabs(LD(h.t) - tRef) / tRef) / ulp;
        worst = std::max(worst, err);
        // Reported separately: hits steeper than ~6 and 60 degrees.
        double cosine = std::fabs(dot(h.ng, r.d));
        if (cosine > 0.1) worstSteep = std::max(worstSteep, err);
        if (cosine > 0.5) worstHalf = std::max(worstHalf, err);
        worstScaled = std::max(worstScaled, err * cosine);
      }
      worstAll = std::max(worstAll, worst);
      std::printf(
          "[quadric] %-6s %-8s %-13s: %d hits, worst |t - t_ref| = %.2f ulp(t) "
          "(%.2f at cos > 0.1, %.2f at cos > 0.5; max err*cos %.2f), %d hit/miss disagreements\n",
          backendName(GetParam()).c_str(),
          kind == ShapeKind::Sphere     ? "sphere"
          : kind == ShapeKind::Cylinder ? "cylinder"
          : kind == ShapeKind::Cone     ? "cone"
                                        : "torus",
          pl.name, hits, worst, worstSteep, worstHalf, worstScaled, missMismatch);
      // The target, 8 double ulps of t, for every hit. Grazing hits are
      // ill-conditioned (an ulp of the object-space ray moves t by 1/cos
      // ulps); shape.cpp refines them in long double, without which this
      // case reached 77,000 ulps near tangency. The steep-hit figures and
      // the conditioned error |t - t_ref| * cos are printed alongside.
      EXPECT_LE(worst, 8.0) << pl.name;
      EXPECT_LE(worstHalf, 8.0) << pl.name;
      // Disagreements can only be edge grazes (surface points sampled on a
      // silhouette or a cap rim): a handful in 20000.
      EXPECT_LE(missMismatch, raysPerCase / 1000) << pl.name;
      EXPECT_GT(hits, raysPerCase / 2);
    }
  }
  std::printf("[quadric] %s: worst error over all cases %.2f ulp(t)\n",
              backendName(GetParam()).c_str(), worstAll);
}

INSTANTIATE_TEST_SUITE_P(Backends, StressQuadricAccuracy, ::testing::ValuesIn(kBothBackends),
                         backendParamName);

} // namespace
} // namespace lray::stress
