// Pipeline: geometry. The torus in object space.
//
// The surface is h(p) = (rho - R)^2 + y^2 - r^2 = 0, rho = |(p.x, p.z)|: the
// squared distance to the centre circle minus r^2. Along a ray, h's zeros
// are among those of the quartic g(t) = (|p|^2 + R^2 - r^2)^2 - 4 R^2 rho^2
// = h(p) ((rho + R)^2 + y^2 - r^2), and g is monotone between its critical
// points (the roots of its cubic derivative, split by the roots of the
// quadratic second derivative), so each monotone piece holds at most one of
// h's zeros. The pieces come from the quartic's coefficients; which piece
// holds a zero, and where, is decided by h itself, evaluated at points of
// the ray (it has no large cancelling terms near the surface, unlike g's
// coefficients): a zero is bracketed by a sign change of h and found by
// bisection with Illinois steps down to adjacent doubles. Grazing hits are
// refined further in long double by shape.cpp (refine below).
#include "geometry/shapes/torus.h"


#include <algorithm>
#include <limits>

namespace lray {

namespace {

/// The squared distance of p to the centre circle minus r^2.
double distanceFunction(const Vec3 &p, double major, double minor) {
  double rho = std::sqrt(p.x * p.x + p.z * p.z);
  double a = rho - major;
  return a * a + p.y * p.y - minor * minor;
}

/// The zero of f in [a, b], given fa = f(a) and fb = f(b) of opposite signs
/// (or one of them zero): bisection with Illinois steps, to adjacent doubles.
template <class F> double bracketedRoot(F f, double a, double b, double fa, double fb) {
  if (fa == 0) return a;
  if (fb == 0) return b;
  int side = 0;
  for (int i = 0; i < 200; ++i) {
    // Illinois regula falsi, falling back to the midpoint when it stalls.
    double m = (a * fb - b * fa) / (fb - fa);
    if (!(m > a && m < b) || i % 4 == 3) m = a + (b - a) / 2;
    if (!(m > a && m < b)) break; // a and b are adjacent doubles
    double fm = f(m);
    if (fm == 0) return m;
    if ((fm < 0) == (fa < 0)) {
      a = m;
      fa = fm;
      if (side == -1) fb /= 2;
      side = -1;
    } else {
      b = m;
      fb = fm;
      if (side == 1) fa /= 2;
      side = 1;
    }
  }
  // The end nearer the sign change of |f|: the bracket is a few ulps wide.
  return std::fabs(fa) < std::fabs(fb) ? a : b;
}

/// Polynomial c[0] + c[1] t + ... + c[n] t^n by Horner's rule.
template <int N> double horner(const double (&c)[N], double t) {
  double v = c[N - 1];
  for (int i = N - 2; i >= 0; --i) v = v * t + c[i];
  return v;
}

/// The roots in (lo, hi) of the polynomial c (degree N - 1) which is
/// monotone between consecutive `breaks` (sorted, inside (lo, hi)), in
/// increasing order: one bisection per sign change.
template <int N>
int monotoneRoots(const double (&c)[N], double lo, double hi, const double *breaks, int nBreaks,
                  double *roots) {
  int n = 0;
  double a = lo, fa = horner(c, lo);
  for (int k = 0; k <= nBreaks; ++k) {
    double b = k < nBreaks ? breaks[k] : hi;
    double fb = horner(c, b);
    if ((fa < 0) != (fb < 0) || fb == 0)
      roots[n++] = bracketedRoot([&](double t) { return horner(c, t); }, a, b, fa, fb);
    a = b;
    fa = fb;
  }
  return n;
}

/// [lo, hi] of the ray inside the box |x|, |z| <= e, |y| <= r (slabs),
/// from ray.tMin on. Not clipped to tMax: the pieces and the bisection
/// brackets, and so the root's last bits, must not depend on how far a
/// backend's query reaches (its tMax is its nearest hit so far).
bool boxInterval(const Ray &ray, double e, double r, double &lo, double &hi) {
  const double half[3] = {e, r, e};
  lo = ray.tMin;
  hi = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    double o = ray.o[axis], d = ray.d[axis];
    if (d == 0) {
      if (std::fabs(o) > half[axis]) return false;
      continue;
    }
    double t0 = (-half[axis] - o) / d, t1 = (half[axis] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  return lo <= hi;
}

} // namespace

Bounds3 Torus::worldBounds(const Mat4 &mat) const {
  // Support function of circle (+) ball along world axis i: R times the
  // norm of (M_i0, M_i2) plus r times the norm of row i.
  const auto &m = mat.m;
  Vec3 c{m[0][3], m[1][3], m[2][3]};
  Vec3 e;
  for (int i = 0; i < 3; ++i)
    e[i] = major * std::hypot(m[i][0], m[i][2]) +
           minor * std::sqrt(m[i][0] * m[i][0] + m[i][1] * m[i][1] + m[i][2] * m[i][2]);
  return {c - e, c + e};
}

namespace {

/// The pieces of the ray (from ray.tMin on) inside the torus's box between
/// the quartic's critical points: h has at most one zero in each. False
/// when the ray misses the box.
struct TorusPieces {
  double lo, hi;
  double breaks[3];
  int count = 0;
};

bool torusPieces(const Ray &ray, double R, double r, TorusPieces &p) {
  if (!boxInterval(ray, R + r, r, p.lo, p.hi)) return false;
  const double lo = p.lo, hi = p.hi;
  const Vec3 &o = ray.o, &d = ray.d;
  // g(t) = (dd t^2 + 2 od t + k)^2 - 4 R^2 (a t^2 + 2 b t + c).
  double dd = dot(d, d), od = dot(o, d), k = dot(o, o) + (R * R - r * r);
  double a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z;
  if (!(dd > 0)) return false;
  double r4 = 4 * R * R;
  const double g[5] = {k * k - r4 * c, 4 * od * k - 2 * r4 * b,
                       4 * od * od + 2 * dd * k - r4 * a, 4 * dd * od, dd * dd};
  const double g1[4] = {g[1], 2 * g[2], 3 * g[3], 4 * g[4]};
  const double g2[3] = {2 * g[2], 6 * g[3], 12 * g[4]};
  // Critical points of g' (roots of g''), then of g (roots of g').
  double breaks2[2];
  int n2 = 0;
  {
    double disc = g2[1] * g2[1] - 4 * g2[2] * g2[0];
    if (disc > 0) {
      double s = std::sqrt(disc);
      double q = -0.5 * (g2[1] + std::copysign(s, g2[1]));
      double x0 = q / g2[2], x1 = q != 0 ? g2[0] / q : x0;
      if (x0 > x1) std::swap(x0, x1);
      for (double x : {x0, x1})
        if (x > lo && x < hi) breaks2[n2++] = x;
    }
  }
  p.count = monotoneRoots(g1, lo, hi, breaks2, n2, p.breaks);
  return true;
}

} // namespace

bool Torus::intersect(const Ray &ray, ObjectHit &hit) const {
  const double R = major, r = minor;
  TorusPieces pieces;
  if (!torusPieces(ray, R, r, pieces)) return false;
  const int n1 = pieces.count;
  const double *breaks1 = pieces.breaks;
  // Each piece of [lo, hi] between critical points holds at most one zero
  // of h: the first sign change of h, in order along the ray, is the hit.
  auto h = [&](double t) { return distanceFunction(ray.at(t), R, r); };
  double a0 = pieces.lo, h0 = h(pieces.lo);
  for (int i = 0; i <= n1 && a0 < ray.tMax; ++i) {
    double b1 = i < n1 ? breaks1[i] : pieces.hi;
    if (!(b1 > a0) && i < n1) continue;
    double h1 = h(b1);
    if ((h0 < 0) != (h1 < 0) || (h1 == 0 && h0 != 0)) {
      double t = bracketedRoot(h, a0, b1, h0, h1);
      if (inOpenRange(ray, t)) {
        hit.t = t;
        hit.part = 0;
        return true;
      }
    }
    a0 = b1;
    h0 = h1;
  }
  return false;
}

int Torus::spans(const Ray &ray, Span *out) const {
  const double R = major, r = minor;
  Ray line = ray;
  line.tMin = -std::numeric_limits<double>::infinity();
  TorusPieces pieces;
  if (!torusPieces(line, R, r, pieces)) return 0;
  // Inside is h < 0: each sign change of h is a crossing, so entries and
  // exits alternate by construction (a touch, h = 0 between two positive
  // values, is none). The box's faces are outside or on the torus.
  auto h = [&](double t) { return distanceFunction(line.at(t), R, r); };
  int n = 0;
  bool inside = false;
  double a0 = pieces.lo, h0 = h(pieces.lo);
  if (h0 < 0) { // rounding at the box's face
    out[0] = {a0, a0, 0, 0};
    inside = true;
  }
  for (int i = 0; i <= pieces.count; ++i) {
    double b1 = i < pieces.count ? pieces.breaks[i] : pieces.hi;
    if (!(b1 > a0) && i < pieces.count) continue;
    double h1 = h(b1);
    if ((h0 < 0) != (h1 < 0)) {
      double t = bracketedRoot(h, a0, b1, h0, h1);
      if (!inside) {
        if (n == kMaxSpans) break;
        out[n] = {t, t, 0, 0};
      } else {
        out[n++].t1 = t;
      }
      inside = !inside;
    }
    a0 = b1;
    h0 = h1;
  }
  if (inside) out[n++].t1 = pieces.hi; // rounding at the box's face
  // Rounding can make an exit equal its entry: no stretch.
  int kept = 0;
  for (int i = 0; i < n; ++i)
    if (out[i].t0 < out[i].t1) out[kept++] = out[i];
  return kept;
}

ObjectSurface Torus::surface(const Ray &ray, const ObjectHit &hit, bool uv) const {
  ObjectSurface s;
  Vec3 p = ray.at(hit.t);
  double rho = std::sqrt(p.x * p.x + p.z * p.z);
  // The nearest point of the centre circle (any, on the axis), then snap
  // onto the tube around it.
  Vec3 q = rho > 0 ? Vec3(p.x * (major / rho), 0, p.z * (major / rho)) : Vec3(major, 0, 0);
  Vec3 n = p - q;
  double len = length(n);
  n = len > 0 ? n / len : Vec3(q.x / major, 0, q.z / major);
  s.p = q + n * minor;
  s.n = n;
  if (!uv) return s;
  s.u = turnFraction(s.p.x, s.p.z);
  double radial = n.x * q.x / major + n.z * q.z / major; // n along the outward radius
  double a = std::atan2(n.y, radial);
  if (a < 0) a += 2 * kPi;
  double v = a / (2 * kPi);
  s.v = v < 1 ? v : 0;
  return s;
}

std::optional<Wide> Torus::refine(const WideRay &ray, Wide s, Wide shift, int) const {
  const Wide R = major, r = minor;
  return newtonRefine(ray, s, shift, [&](const WideVec &p, const WideVec &d) {
    Wide rho = std::sqrt(p.x * p.x + p.z * p.z);
    Wide a = rho - R;
    Wide drho = rho > 0 ? (p.x * d.x + p.z * d.z) / rho : Wide(0);
    return WideSlope{a * a + p.y * p.y - r * r, 2 * (a * drho + p.y * d.y)};
  });
}

} // namespace lray
