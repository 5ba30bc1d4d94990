// Randomised tests for src/geometry/shape: 1e5 rays per analytic shape under
// random affine transforms, checked against an independent long double
// reference intersection (same object-space definition, naive formulas).
#include "geometry/shape.h"
#include "long_double_root.h"
#include "shape_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace lray {
namespace {

using LD = long double;

struct V3L {
  LD x, y, z;
};

V3L applyL(const Mat4 &mat, const Vec3 &p, bool point) {
  const auto &m = mat.m;
  LD w = point ? 1 : 0;
  return {m[0][0] * (LD)p.x + m[0][1] * (LD)p.y + m[0][2] * (LD)p.z + m[0][3] * w,
          m[1][0] * (LD)p.x + m[1][1] * (LD)p.y + m[1][2] * (LD)p.z + m[1][3] * w,
          m[2][0] * (LD)p.x + m[2][1] * (LD)p.y + m[2][2] * (LD)p.z + m[2][3] * w};
}

/// Reference result: closest t > 0 (or none), and whether the case is too
/// close to a decision boundary (grazing, rim, edge) for a strict check.
struct Reference {
  bool hit = false;
  LD t = 0;
  bool ambiguous = false;
  LD shift = 0; ///< the object-space origin was moved to o + shift d
};

constexpr LD kTol = 1e-7L;

void consider(Reference &r, LD t, bool inside, LD margin) {
  if (std::fabs(margin) < kTol) r.ambiguous = true;
  t += r.shift;
  if (!(t > 0) || !inside) return;
  if (!r.hit || t < r.t) {
    r.hit = true;
    r.t = t;
  }
}

void quadratic(Reference &r, LD a, LD h, LD c, const V3L &o, const V3L &d, bool cone) {
  if (a == 0) return;
  LD disc = h * h - a * c;
  LD scale = h * h + std::fabs(a * c);
  if (std::fabs(disc) < kTol * scale) r.ambiguous = true;
  if (disc < 0) return;
  LD s = std::sqrt(disc);
  for (LD t : {(-h - s) / a, (-h + s) / a}) {
    LD y = o.y + t * d.y;
    bool inside = y >= 0 && y <= 1;
    LD margin = std::min(std::fabs(y), std::fabs(y - 1));
    if (cone && std::fabs(y - 1) < 1e-4L) r.ambiguous = true; // near the apex
    consider(r, t, inside, margin);
  }
}

void cap(Reference &r, LD planeY, const V3L &o, const V3L &d) {
  if (d.y == 0) return;
  LD t = (planeY - o.y) / d.y;
  LD x = o.x + t * d.x, z = o.z + t * d.z;
  LD r2 = x * x + z * z;
  consider(r, t, r2 <= 1, r2 - 1);
}

/// Torus (major R, minor r) along the object-space ray o + t d: h(t) =
/// (rho - R)^2 + y^2 - r^2 sampled densely over the bounding sphere's chord,
/// each sign change bisected in long double; near-tangent rays (a small
/// sampled |h| with no sign change, or a root the ray meets at a grazing
/// angle) are ambiguous.
void torusReference(Reference &r, LD R, LD rm, const V3L &o, const V3L &d) {
  auto h = [&](LD t) {
    LD x = o.x + t * d.x, y = o.y + t * d.y, z = o.z + t * d.z;
    LD a = std::sqrt(x * x + z * z) - R;
    return a * a + y * y - rm * rm;
  };
  LD dd = d.x * d.x + d.y * d.y + d.z * d.z, od = o.x * d.x + o.y * d.y + o.z * d.z;
  LD rb = R + rm, disc = od * od - dd * (o.x * o.x + o.y * o.y + o.z * o.z - rb * rb);
  if (disc <= 0) return;
  LD t0 = (-od - std::sqrt(disc)) / dd, t1 = (-od + std::sqrt(disc)) / dd;
  const int kSamples = 1000;
  LD step = (t1 - t0) / kSamples, prevT = t0, prevH = h(t0);
  for (int i = 1; i <= kSamples; ++i) {
    LD t = t0 + step * i, ht = h(t);
    if (std::fabs(ht) < 1e-4L * rm * rm && (ht < 0) == (prevH < 0)) r.ambiguous = true;
    if ((ht < 0) != (prevH < 0)) {
      LD root = testing::bisectRoot(h, prevT, t), eps = 1e-9L * (1 + std::fabs(root));
      LD slope = std::fabs(h(root + eps) - h(root - eps)) / (2 * eps);
      // |dh/dt| = 2 r |d| cos at the surface.
      consider(r, root, true, slope / (2 * rm * std::sqrt(dd)) < 1e-3L ? 0 : 1);
    }
    prevT = t;
    prevH = ht;
  }
}

Reference reference(const Entity &e, const Ray &world) {
  const Mat4 &inv = e.worldFromObject.inverseMatrix();
  V3L o = applyL(inv, world.o, true), d = applyL(inv, world.d, false);
  Reference r;
  // Work from the ray's closest approach to the shape's centre, so that
  // distant origins do not cost the reference its own precision.
  LD cy = e.kind() == ShapeKind::Cylinder || e.kind() == ShapeKind::Cone ? 0.5L : 0.0L;
  r.shift = (-o.x * d.x + (cy - o.y) * d.y - o.z * d.z) / (d.x * d.x + d.y * d.y + d.z * d.z);
  o = {o.x + r.shift * d.x, o.y + r.shift * d.y, o.z + r.shift * d.z};
  switch (e.kind()) {
  case ShapeKind::Sphere: {
    LD a = d.x * d.x + d.y * d.y + d.z * d.z, h = o.x * d.x + o.y * d.y + o.z * d.z;
    LD c = o.x * o.x + o.y * o.y + o.z * o.z - 1;
    LD disc = h * h - a * c;
    if (std::fabs(disc) < kTol * (h * h + std::fabs(a * c))) r.ambiguous = true;
    if (disc >= 0) {
      LD s = std::sqrt(disc);
      consider(r, (-h - s) / a, true, 1);
      consider(r, (-h + s) / a, true, 1);
    }
    break;
  }
  case ShapeKind::Cylinder: {
    LD a = d.x * d.x + d.z * d.z, h = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - 1;
    quadratic(r, a, h, c, o, d, false);
    if (!isOpen(e)) {
      cap(r, 0, o, d);
      cap(r, 1, o, d);
    }
    break;
  }
  case ShapeKind::Cone: {
    LD k = 1 - o.y;
    LD a = d.x * d.x + d.z * d.z - d.y * d.y, h = o.x * d.x + o.z * d.z + k * d.y;
    LD c = o.x * o.x + o.z * o.z - k * k;
    quadratic(r, a, h, c, o, d, true);
    if (!isOpen(e)) cap(r, 0, o, d);
    break;
  }
  case ShapeKind::Cube: {
    LD lo = -1e300L, hi = 1e300L;
    LD oa[3] = {o.x, o.y, o.z}, da[3] = {d.x, d.y, d.z};
    for (int i = 0; i < 3; ++i) {
      if (da[i] == 0) {
        if (std::fabs(oa[i]) > 0.5L) return r;
        continue;
      }
      LD t0 = (-0.5L - oa[i]) / da[i], t1 = (0.5L - oa[i]) / da[i];
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
    }
    LD span = std::max(std::fabs(lo), std::fabs(hi));
    if (std::fabs(hi - lo) < kTol * span) r.ambiguous = true; // through an edge
    if (lo > hi) return r;
    consider(r, lo, true, lo + r.shift);
    if (!r.hit) consider(r, hi, true, hi + r.shift);
    // Points near an edge of the entry face: which face is "first" is a tie.
    break;
  }
  case ShapeKind::Plane:
    if (d.y != 0) consider(r, -o.y / d.y, true, 1);
    break;
  case ShapeKind::Torus: {
    const Torus &t = std::get<Torus>(e.shape);
    torusReference(r, t.major, t.minor, o, d);
    break;
  }
  case ShapeKind::Mesh:
  case ShapeKind::Csg: break;
  }
  if (r.hit && r.t < kTol) r.ambiguous = true;
  return r;
}

Transform randomTransform(std::mt19937_64 &rng) {
  std::uniform_real_distribution<double> u(-1, 1), s(0.3, 3);
  Vec3 axis{u(rng), u(rng), u(rng)};
  if (length(axis) < 0.1) axis = {0, 1, 0};
  return Transform::translate({3 * u(rng), 3 * u(rng), 3 * u(rng)}) *
         Transform::rotate(axis, 180 * u(rng)) * Transform::scale(s(rng), s(rng), s(rng));
}

struct RandomCase {
  ShapeKind kind;
  bool open;
};

class ShapeRandom : public ::testing::TestWithParam<RandomCase> {};

TEST_P(ShapeRandom, AgreesWithLongDoubleReference) {
  std::mt19937_64 rng(1234 + static_cast<int>(GetParam().kind) * 7 + GetParam().open);
  std::uniform_real_distribution<double> u(-1, 1);
  const int kEntities = 100, kRaysPerEntity = 1000;
  int checked = 0, hits = 0, insideStarts = 0;
  for (int ei = 0; ei < kEntities; ++ei) {
    Entity e;
    e.shape = makeShape(GetParam().kind);
    setOpen(e, GetParam().open);
    e.worldFromObject = randomTransform(rng);
    Bounds3 b = shapeWorldBounds(e);
    Vec3 c = b.center(), ext = b.diagonal() * 0.6;
    for (int k = 0; k < kRaysPerEntity; ++k) {
      // Aim at a random point of (slightly more than) the bounds, from a
      // random origin outside or, one time in five, inside the bounds.
      Vec3 target = c + Vec3(u(rng) * ext.x, u(rng) * ext.y, u(rng) * ext.z);
      Vec3 o;
      if (k % 5 == 0) {
        o = e.worldFromObject.applyPoint({0.3 * u(rng), 0.3 + 0.2 * u(rng), 0.3 * u(rng)});
        target = o + Vec3(u(rng), u(rng), u(rng));
        ++insideStarts;
      } else {
        o = c + Vec3(u(rng), u(rng), u(rng)) * (10 * length(ext));
      }
      Ray ray{o, (target - o) * (0.5 + u(rng) * 0.4)};
      Reference ref = reference(e, ray);
      Hit h;
      bool hit = intersectShape(e, 3, ray, h);
      EXPECT_EQ(hit, occludedShape(e, ray));
      if (GetParam().kind == ShapeKind::Sphere) {
        EXPECT_EQ(hit, occludedStillSphere(e, ray, ray.tMax));
      }
      if (ref.ambiguous) continue;
      ++checked;
      ASSERT_EQ(hit, ref.hit) << "entity " << ei << " ray " << k;
      if (!hit) continue;
      ++hits;
      ASSERT_NEAR(h.t, (double)ref.t, 1e-6 * (double)ref.t) << "entity " << ei << " ray " << k;
      // The hit point lies on the ray and the normal is unit.
      Vec3 onRay = ray.at(h.t);
      ASSERT_LT(length(onRay - h.p), 1e-9 * (1 + length(h.p)));
      ASSERT_NEAR(length(h.ng), 1, 1e-12);
      ASSERT_GE(h.u, 0);
      ASSERT_LE(h.u, 1);
      ASSERT_GE(h.v, 0);
      ASSERT_LE(h.v, 1);
      ASSERT_GE(h.pError, 0);
    }
  }
  // The generator must exercise the shape, not just skip it.
  EXPECT_GT(checked, kEntities * kRaysPerEntity * 95 / 100);
  EXPECT_GT(hits, checked / 5);
  EXPECT_GT(insideStarts, 0);
}

TEST_P(ShapeRandom, DistantOriginsKeepThePointAccurate) {
  // From 1e6 away the quadric coefficients cancel unless the ray is
  // re-origined; the hit point must stay within a few ulps of the distance.
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  Entity e;
  e.shape = makeShape(GetParam().kind);
  setOpen(e, GetParam().open);
  const double dist = 1e6;
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    Vec3 target{0.5 * u(rng), 0.5 + 0.4 * u(rng), 0.5 * u(rng)};
    Vec3 dir{u(rng), u(rng), u(rng)};
    if (length(dir) < 0.1) continue;
    Vec3 o = target + dir * (dist / length(dir));
    Ray ray{o, target - o};
    Reference ref = reference(e, ray);
    Hit h;
    bool hit = intersectShape(e, 0, ray, h);
    if (ref.ambiguous || !ref.hit) continue;
    ASSERT_TRUE(hit) << i;
    ++checked;
    for (int k = 0; k < 3; ++k) {
      LD pk = (LD)ray.o[k] + ref.t * (LD)ray.d[k];
      ASSERT_NEAR(h.p[k], (double)pk, 1e-14 * dist) << i;
    }
  }
  EXPECT_GT(checked, 1000);
}

std::string caseName(const ::testing::TestParamInfo<RandomCase> &param) {
  Entity e;
  e.shape = makeShape(param.param.kind);
  return std::string(shapeName(e.shape)) + (param.param.open ? "Open" : "");
}

INSTANTIATE_TEST_SUITE_P(Shapes, ShapeRandom,
                         ::testing::Values(RandomCase{ShapeKind::Sphere, false},
                                           RandomCase{ShapeKind::Cylinder, false},
                                           RandomCase{ShapeKind::Cylinder, true},
                                           RandomCase{ShapeKind::Cone, false},
                                           RandomCase{ShapeKind::Cone, true},
                                           RandomCase{ShapeKind::Cube, false},
                                           RandomCase{ShapeKind::Torus, false}),
                         caseName);

} // namespace
} // namespace lray
