// Pipeline: geometry. The cone in object space (lua/README.md, "Entities"): base radius 1
// at y = 0, apex at (0, 1, 0), base capped unless `open`.
#include "geometry/shapes/cone.h"

#include "math/transform.h"
#include "geometry/shapes/disc_bounds.h"

#include <algorithm>
#include <limits>

namespace lray {

Bounds3 Cone::worldBounds(const Mat4 &mat) const {
  // The convex hull of the base disc and the apex.
  Bounds3 b = discBounds(mat, 0);
  b.extend(affinePoint(mat, {0, 1, 0}));
  return b;
}

bool Cone::intersect(const Ray &ray, ObjectHit &hit) const {
  const Vec3 &o = ray.o, &d = ray.d;
  bool found = false;
  double best = ray.tMax;
  // Side: x^2 + z^2 = (1 - y)^2 with 0 <= y <= 1 (the other nappe, y > 1,
  // is rejected). With k = 1 - y: a t^2 + 2 h t + c = 0.
  double k = 1 - o.y;
  double a = d.x * d.x + d.z * d.z - d.y * d.y;
  double h = o.x * d.x + o.z * d.z + k * d.y;
  double c = o.x * o.x + o.z * o.z - k * k;
  double disc = differenceOfProducts(h, h, a, c);
  // A ray through the apex has a double root (disc = 0 exactly); keep it
  // when rounding made the discriminant slightly negative. The bound is on
  // the rounding of a, h and c themselves (c cancels: o.o ~ k^2 near the
  // apex), not only on h^2 - a c: a steep ray through the apex measured
  // -8.9e-16 relative to h^2 + |a c|, past a bound on the product alone.
  double aAbs = d.x * d.x + d.z * d.z + d.y * d.y;
  double hAbs = std::fabs(o.x * d.x) + std::fabs(o.z * d.z) + std::fabs(k * d.y);
  double cAbs = o.x * o.x + o.z * o.z + k * k;
  double discError = 8 * 0x1p-53 * (h * h + std::fabs(a * c) + 2 * std::fabs(h) * hAbs +
                                    std::fabs(a) * cAbs + std::fabs(c) * aAbs);
  if (disc < 0 && disc > -discError) disc = 0;
  // Near a double root (through the apex) the root itself is off by the
  // coefficients' error over |a|: allow that much in the y range below.
  double rootError = disc <= discError && a != 0
                         ? 32 * 0x1p-53 * std::fabs(d.y) * hAbs / std::fabs(a)
                         : 0;
  if (disc >= 0) {
    double roots[2] = {std::nan(""), std::nan("")};
    if (a == 0) {
      // Ray parallel to a generator line: a single root (none if h = 0).
      if (h != 0) roots[0] = -c / (2 * h);
    } else {
      quadraticRoots(a, h, c, disc, roots[0], roots[1]);
    }
    for (double t : roots) {
      if (!inOpenRange(ray, t) || t >= best) continue;
      double y = o.y + t * d.y;
      // A ray through the apex has its double root there, which rounding
      // can put tens of ulps past y = 1 (t and y both come from rounded
      // coefficients); rejecting it let such rays through the apex into
      // the cone. Accept within that error: Cone::surface clamps the point
      // onto the cone.
      // Capped at sqrt(eps): a root further out is not a rounding artefact
      // (and with |a| tiny the estimate above would admit the other nappe).
      double yTolerance = std::min(
          0x1p-26, 64 * 0x1p-53 * (1 + std::fabs(o.y) + std::fabs(t * d.y)) +
                       rootError * (1 + std::fabs(t) * aAbs / std::max(hAbs, 1e-300)));
      if (y < -yTolerance || y > 1 + yTolerance) continue;
      best = t;
      hit.t = t;
      hit.part = 0;
      found = true;
      break;
    }
  }
  if (!open && d.y != 0) {
    double t = -o.y / d.y;
    if (inOpenRange(ray, t) && t < best) {
      double x = o.x + t * d.x, z = o.z + t * d.z;
      if (x * x + z * z <= 1) {
        hit.t = t;
        hit.part = 1;
        found = true;
      }
    }
  }
  return found;
}

int Cone::spans(const Ray &ray, Span *out) const {
  const Vec3 &o = ray.o, &d = ray.d;
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Inside both nappes: q(t) = a t^2 + 2 h t + c <= 0 (intersect's
  // coefficients), one or two stretches of the line ...
  double k = 1 - o.y;
  double a = d.x * d.x + d.z * d.z - d.y * d.y;
  double h = o.x * d.x + o.z * d.z + k * d.y;
  double c = o.x * o.x + o.z * o.z - k * k;
  double disc = differenceOfProducts(h, h, a, c);
  Span in[2];
  int n = 0;
  if (a == 0) {
    // Parallel to a generator: q is linear.
    if (h != 0) {
      double t = -c / (2 * h);
      in[n++] = h > 0 ? Span{-inf, t, -1, 0} : Span{t, inf, 0, -1};
    } else if (c < 0) {
      in[n++] = {-inf, inf, -1, -1};
    }
  } else if (disc > 0) {
    double t0, t1;
    quadraticRoots(a, h, c, disc, t0, t1);
    if (a > 0) {
      in[n++] = {t0, t1, 0, 0};
    } else {
      in[n++] = {-inf, t0, -1, 0};
      in[n++] = {t1, inf, 0, -1};
    }
  } else if (a < 0) {
    in[n++] = {-inf, inf, -1, -1}; // q < 0 along the whole line
  }
  // ... cut to the slab 0 <= y <= 1, which holds only the lower nappe: the
  // base (part 1) and the apex plane (the side's tip, part 0).
  double lo = -inf, hi = inf;
  int loPart = -1, hiPart = -1;
  if (d.y != 0) {
    double t0 = (0.0 - o.y) / d.y, t1 = (1.0 - o.y) / d.y;
    lo = std::min(t0, t1);
    hi = std::max(t0, t1);
    loPart = t0 < t1 ? 1 : 0;
    hiPart = t0 < t1 ? 0 : 1;
  } else if (!(o.y > 0 && o.y < 1)) {
    return 0;
  }
  int count = 0;
  for (int i = 0; i < n; ++i) {
    Span s = in[i];
    if (lo > s.t0) {
      s.t0 = lo;
      s.part0 = loPart;
    }
    if (hi < s.t1) {
      s.t1 = hi;
      s.part1 = hiPart;
    }
    if (s.t0 < s.t1) out[count++] = s;
  }
  return count;
}

ObjectSurface Cone::surface(const Ray &ray, const ObjectHit &hit, bool uv) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  if (hit.part == 0) {
    p.y = std::clamp(p.y, 0.0, 1.0);
    double r = std::sqrt(p.x * p.x + p.z * p.z);
    double k = 1 - p.y;
    // Snap radially onto the cone; at the apex the normal is taken as +y.
    if (r > 0) {
      p.x *= k / r;
      p.z *= k / r;
    }
    s.n = k > 0 && r > 0 ? Vec3(p.x, k, p.z) : Vec3(0, 1, 0);
    if (uv) s.u = turnFraction(p.x, p.z);
    s.v = p.y;
  } else {
    p.y = 0;
    s.n = {0, -1, 0};
    s.u = std::clamp((p.x + 1) / 2, 0.0, 1.0);
    s.v = std::clamp((p.z + 1) / 2, 0.0, 1.0);
  }
  s.p = p;
  return s;
}

std::optional<Wide> Cone::refine(const WideRay &ray, Wide s, Wide shift, int part) const {
  if (part != 0) return planeRefine(ray.o.y, ray.d.y, 0, s);
  return newtonRefine(ray, s, shift, [](const WideVec &p, const WideVec &d) {
    Wide k = 1 - p.y; // x^2 + z^2 = (1 - y)^2
    return WideSlope{p.x * p.x + p.z * p.z - k * k, 2 * (p.x * d.x + p.z * d.z + k * d.y)};
  });
}

} // namespace lray
