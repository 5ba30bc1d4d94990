// Pipeline: shading. See emitters.h.
#include "shading/emitters.h"

#include "geometry/csg_ray.h"
#include "geometry/csg_tree.h"
#include "geometry/shape.h"
#include "math/transform.h"
#include "math/onb.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lray {

namespace {

double mean(const Color &c) { return (c.r + c.g + c.b) / 3; }

/// A spindle torus's surface (minor >= major: an apple) is the tube's
/// part outside the axis, R + r cos b >= 0: tube angles |b| up to this.
double spindleTubeAngle(const Torus &t) { return std::acos(-t.major / t.minor); }

/// |det| of the linear part: how the transform scales volumes; its 2/3
/// power estimates how it scales areas (for choosing among emitters only).
double areaScale(const Transform &t) { return std::pow(std::fabs(t.matrix().det3()), 2.0 / 3); }

} // namespace

bool Emitters::keepsRound(const Transform &t) {
  const auto &m = t.matrix().m;
  const Vec3 a(m[0][0], m[1][0], m[2][0]), b(m[0][1], m[1][1], m[2][1]),
      c(m[0][2], m[1][2], m[2][2]);
  const double la = length(a), lb = length(b), lc = length(c);
  const double tolerance = 1e-9 * la;
  return la > 0 && std::fabs(la - lb) <= tolerance && std::fabs(la - lc) <= tolerance &&
         std::fabs(dot(a, b)) <= tolerance * la && std::fabs(dot(a, c)) <= tolerance * la &&
         std::fabs(dot(b, c)) <= tolerance * la;
}

Emitters::Ball Emitters::ballAt(const Entry &entry, float time) const {
  const Entity &e = shapeOf(entry);
  const Mat4 m = e.motion ? e.motion->matrixAt(time) : e.worldFromObject.matrix();
  return {Vec3(m.m[0][3], m.m[1][3], m.m[2][3]),
          length(Vec3(m.m[0][0], m.m[1][0], m.m[2][0]))};
}

double Emitters::triangleArea(const Entry &entry, float time) const {
  if (!entry.moves) return entry.area;
  const Entity &e = scene_.entities[entry.entity];
  const Transform placement = e.placementAt(time);
  const uint32_t *v = e.mesh->triangles[entry.part].v;
  Vec3 corner[3];
  for (int k = 0; k < 3; ++k)
    corner[k] = placement.applyPoint(e.vertexMotion ? e.vertexMotion->position(v[k], time)
                                                    : toVec3(e.mesh->positions[v[k]]));
  return 0.5 * length(cross(corner[1] - corner[0], corner[2] - corner[0]));
}

double Emitters::coneSize(const Ball &ball, const Vec3 &ref) {
  const Vec3 toCentre = ball.centre - ref;
  const double d2 = dot(toCentre, toCentre), r2 = ball.radius * ball.radius;
  if (!(d2 > r2 * (1 + 1e-9))) return 0; // inside, or on the surface: by area
  const double sin2 = r2 / d2;
  return sin2 / (1 + std::sqrt(1 - sin2)); // 1 - cos theta_max, without cancellation
}

double Emitters::conePdfArea(const Entry &entry, double cone, const Vec3 &ref, const Vec3 &p,
                             const Vec3 &n) {
  const Vec3 toPoint = p - ref;
  const double d2 = dot(toPoint, toPoint);
  const double cosLight = std::fabs(dot(n, toPoint)) / std::sqrt(d2);
  return entry.probability / (2 * std::numbers::pi * cone) * cosLight / d2;
}

std::optional<std::pair<Emitters::Kind, double>> Emitters::solidKind(const Entity &e) {
  constexpr double pi = std::numbers::pi;
  switch (e.kind()) {
  case ShapeKind::Sphere:
    return std::pair{Kind::Sphere, 4 * pi};
  case ShapeKind::Cube:
    return std::pair{Kind::Cube, 6.0};
  case ShapeKind::Cylinder: // the side (2 pi) and two caps (pi each) unless open
    return std::pair{Kind::Cylinder, pi * (std::get<Cylinder>(e.shape).open ? 2 : 4)};
  case ShapeKind::Cone: // the side (pi sqrt 2) and the base (pi) unless open
    return std::pair{Kind::Cone, pi * (std::sqrt(2.0) + (std::get<Cone>(e.shape).open ? 0 : 1))};
  case ShapeKind::Torus: {
    const Torus &t = std::get<Torus>(e.shape);
    if (!(t.minor > 0 && t.major >= 0)) return std::nullopt;
    if (t.major > t.minor) // a ring torus: area 4 pi^2 R r
      return std::pair{Kind::Torus, 4 * pi * pi * t.major * t.minor};
    // A spindle torus (an apple): the tube's part with R + r cos b >= 0,
    // |b| <= b_max (sampleTorus), of area 4 pi r (R b_max + r sin b_max).
    const double bMax = spindleTubeAngle(t);
    return std::pair{Kind::Torus, 4 * pi * t.minor * (t.major * bMax + t.minor * std::sin(bMax))};
  }
  default:
    return std::nullopt; // a Plane (no area), a Mesh (by triangles), a CSG (by leaves)
  }
}

Emitters::Emitters(const Scene &scene) : scene_(scene), firstEntry_(scene.entities.size(), -1) {
  std::vector<double> power;
  auto emissionOf = [&](const Entity &e) -> const Color * {
    if (e.texture >= scene.textures.size()) return nullptr;
    const Color &emission = scene.textures[e.texture].finish.emission;
    return emission.isBlack() ? nullptr : &emission;
  };
  auto addSolid = [&](const Entity &e, uint32_t entity, uint32_t part, bool csgLeaf,
                      const Color &emission) {
    if (const auto kind = solidKind(e)) {
      Entry entry{entity, part, kind->first, csgLeaf, 0, kind->second};
      entry.moves = e.moves();
      if (entry.kind == Kind::Sphere && !csgLeaf) {
        // Round at every step: a turn and an even scale at each, so in
        // between too (the interpolated stretch stays even).
        entry.round = keepsRound(e.worldFromObject);
        for (size_t k = 0; e.motion && k < e.motion->stepCount(); ++k)
          entry.round = entry.round && keepsRound(e.motion->step(k));
      }
      entries_.push_back(entry);
      power.push_back(mean(emission) * kind->second * areaScale(e.worldFromObject));
    }
  };
  for (uint32_t i = 0; i < scene.entities.size(); ++i) {
    const Entity &e = scene.entities[i];
    const size_t first = entries_.size();
    if (e.kind() == ShapeKind::Csg) {
      // Each leaf emits with its own texture's emission.
      if (const auto &tree = std::get<Csg>(e.shape).tree)
        for (uint32_t k = 0; k < tree->leaves.size(); ++k)
          if (const Color *emission = emissionOf(tree->leaves[k].entity))
            addSolid(tree->leaves[k].entity, i, k, true, *emission);
    } else if (const Color *emission = emissionOf(e)) {
      if (e.kind() != ShapeKind::Mesh) {
        addSolid(e, i, 0, false, *emission);
      } else {
        for (uint32_t t = 0; t < e.mesh->triangles.size(); ++t) {
          const uint32_t *v = e.mesh->triangles[t].v;
          const Vec3 a = e.worldFromObject.applyPoint(toVec3(e.mesh->positions[v[0]]));
          const Vec3 b = e.worldFromObject.applyPoint(toVec3(e.mesh->positions[v[1]]));
          const Vec3 c = e.worldFromObject.applyPoint(toVec3(e.mesh->positions[v[2]]));
          const double area = 0.5 * length(cross(b - a, c - a));
          if (!(area > 0)) continue; // a degenerate triangle: nothing to sample
          entries_.push_back({i, t, Kind::Triangle, false, 0, area, e.moves()});
          if (!e.moves()) {
            entries_.back().fixedTriangle = static_cast<int32_t>(fixedTriangles_.size());
            fixedTriangles_.emplace_back(e, t);
          }
          power.push_back(mean(*emission) * area);
        }
      }
    }
    if (entries_.size() > first) firstEntry_[i] = static_cast<int64_t>(first);
  }
  double total = 0;
  for (double p : power)
    total += p;
  if (!(total > 0) || !std::isfinite(total)) {
    entries_.clear();
    fixedTriangles_.clear();
    std::fill(firstEntry_.begin(), firstEntry_.end(), -1);
    return;
  }
  cumulative_.reserve(entries_.size());
  double sum = 0;
  for (size_t k = 0; k < entries_.size(); ++k) {
    entries_[k].probability = power[k] / total;
    sum += entries_[k].probability;
    cumulative_.push_back(sum);
  }
  cumulative_.back() = 1; // no gap at the top from rounding
}

double Emitters::worldAreaFactor(const Transform &placement, const Vec3 &n) {
  // dA_world = |det M| |M^-T n_obj| dA_object with n_obj the unit object
  // normal; with n = M^-T n_obj / |M^-T n_obj| that is |det M| / |M^T n|.
  const auto &m = placement.matrix().m;
  const Vec3 mtn{m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
                 m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
                 m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
  return length(mtn) / std::fabs(placement.matrix().det3());
}

const Entity &Emitters::shapeOf(const Entry &entry) const {
  const Entity &e = scene_.entities[entry.entity];
  return entry.csgLeaf ? std::get<Csg>(e.shape).tree->leaves[entry.part].entity : e;
}

Emitters::Sample Emitters::sample(const Vec3 &ref, float time, Sampler &sampler) const {
  const double pick = sampler.next();
  double u, v;
  sampler.next2D(u, v);
  const size_t k = std::min<size_t>(std::lower_bound(cumulative_.begin(), cumulative_.end(), pick) -
                                        cumulative_.begin(),
                                    entries_.size() - 1);
  const Entry &entry = entries_[k];
  const Entity &e = shapeOf(entry);
  Sample s;
  s.radiance = scene_.textures[e.texture].finish.emission;
  if (entry.kind == Kind::Triangle) {
    // Uniform in the triangle: the square-root map of two numbers.
    const double r = std::sqrt(u);
    if (entry.fixedTriangle >= 0)
      fixedTriangles_[entry.fixedTriangle].surfacePoint(r * (1 - v), r * v, s.p, s.n);
    else
      triangleSurfacePoint(e, entry.part, r * (1 - v), r * v, time, s.p, s.n);
    s.pdfArea = entry.probability / triangleArea(entry, time);
    return s;
  }
  const Ball ball = entry.round ? ballAt(entry, time) : Ball{};
  if (const double cone = entry.round ? coneSize(ball, ref) : 0; cone > 0) {
    // The cone of directions from ref that meet the sphere, uniformly
    // (pbrt-v3's Sphere::Sample): theta from the axis, then the point of
    // the visible cap that direction meets, by its angle alpha at the centre.
    const Vec3 toCentre = ball.centre - ref;
    const double dc = length(toCentre);
    const Vec3 w = toCentre / dc;
    const double sinMax = ball.radius / dc, sin2Max = sinMax * sinMax;
    const double sin2 = sin2Max < 0.00068523 ? sin2Max * u : 1 - std::pow(1 - cone * u, 2);
    const double cosTheta = std::sqrt(std::max(0.0, 1 - sin2));
    const double cosAlpha =
        sin2 / sinMax + cosTheta * std::sqrt(std::max(0.0, 1 - sin2 / sin2Max));
    const double sinAlpha = std::sqrt(std::max(0.0, 1 - cosAlpha * cosAlpha));
    const double phi = 2 * std::numbers::pi * v;
    Vec3 t, b;
    orthonormalBasis(w, t, b);
    s.n = -(t * (sinAlpha * std::cos(phi)) + b * (sinAlpha * std::sin(phi)) + w * cosAlpha);
    s.p = ball.centre + s.n * ball.radius;
    s.pdfArea = conePdfArea(entry, cone, ref, s.p, s.n);
    return s;
  }
  Vec3 pObject, nObject;
  if (entry.kind == Kind::Sphere) {
    const double z = 1 - 2 * u, r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = 2 * std::numbers::pi * v;
    pObject = nObject = Vec3(r * std::cos(phi), r * std::sin(phi), z);
  } else if (entry.kind == Kind::Cylinder || entry.kind == Kind::Cone) {
    sampleRound(entry, u, v, pObject, nObject);
  } else if (entry.kind == Kind::Torus) {
    sampleTorus(std::get<Torus>(e.shape), u, v, pObject, nObject);
  } else { // Cube: a face (of six, equally likely), then a point on it
    const int face = std::min(5, static_cast<int>(u * 6));
    const double a = u * 6 - face - 0.5, b = v - 0.5;
    const double side = face & 1 ? 0.5 : -0.5;
    switch (face / 2) {
    case 0:
      pObject = {side, a, b};
      break;
    case 1:
      pObject = {a, side, b};
      break;
    default:
      pObject = {a, b, side};
      break;
    }
    nObject = Vec3(face / 2 == 0 ? side * 2 : 0, face / 2 == 1 ? side * 2 : 0,
                   face / 2 == 2 ? side * 2 : 0);
  }
  const Transform placement = e.placementAt(time);
  s.p = affinePoint(placement.matrix(), pObject);
  s.n = unitVector(affineNormal(placement.inverseMatrix(), nObject));
  s.pdfArea = entry.probability * worldAreaFactor(placement, s.n) / entry.area;
  if (entry.csgLeaf && !onCsgSurface(entry, s.p, time, s.n)) s.pdfArea = 0;
  return s;
}

bool Emitters::onCsgSurface(const Entry &entry, const Vec3 &p, float time, Vec3 &n) const {
  // A short ray through the point across the leaf's surface: the point is
  // the result's where the CSG code (the operators' rules, coincident
  // surfaces included) finds this leaf's surface there first.
  const Entity &e = scene_.entities[entry.entity];
  const double scale = std::max({1.0, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  const double delta = 1e-7 * scale;
  Ray probe{p + n * delta, -n, 0, 2 * delta};
  probe.time = time; // a moving leaf where it is then
  Hit hit;
  if (!intersectCsg(std::get<Csg>(e.shape), entry.entity, probe, hit)) return false;
  if (hit.primitive != entry.part || std::fabs(hit.t - delta) > 0.5 * delta) return false;
  n = hit.ng; // out of the result (reversed on a subtracted leaf)
  return true;
}

void Emitters::sampleTorus(const Torus &t, double u, double v, Vec3 &p, Vec3 &n) {
  // dA = r (R + r cos b) da db: a uniform around the ring, b by the inverse
  // of its distribution, proportional to R (b - b0) + r (sin b - sin b0)
  // over [b0, b1], found by Newton's method kept inside a bracket (it is
  // increasing there: R + r cos b >= 0). A ring torus: the whole tube,
  // [0, 2 pi]; a spindle torus: the apple's surface, [-b_max, b_max].
  const double R = t.major, r = t.minor;
  const bool ring = R > r;
  const double b0 = ring ? 0 : -spindleTubeAngle(t), b1 = ring ? 2 * std::numbers::pi : -b0;
  const double sin0 = ring ? 0 : std::sin(b0);
  const double target =
      ring ? 2 * std::numbers::pi * R * v : (R * (b1 - b0) + r * (std::sin(b1) - sin0)) * v;
  double lo = b0, hi = b1, b = b0 + (b1 - b0) * v;
  for (int k = 0; k < 60; ++k) {
    const double f = R * (b - b0) + r * (std::sin(b) - sin0) - target;
    if (f > 0) hi = b;
    else lo = b;
    const double step = f / (R + r * std::cos(b));
    double next = b - step;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - b) < 1e-14) {
      b = next;
      break;
    }
    b = next;
  }
  const double a = 2 * std::numbers::pi * u;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
  n = {cb * ca, sb, cb * sa};
  p = {(R + r * cb) * ca, r * sb, (R + r * cb) * sa};
}

void Emitters::sampleRound(const Entry &entry, double u, double v, Vec3 &p, Vec3 &n) const {
  // Uniform by object-space area: the side with its share of the area,
  // else a cap (of two equally likely for a cylinder).
  const bool cylinder = entry.kind == Kind::Cylinder;
  const double side = cylinder ? 2 * std::numbers::pi : std::numbers::pi * std::sqrt(2.0);
  const double sideShare = side / entry.area;
  const double phi = 2 * std::numbers::pi * v;
  const double c = std::cos(phi), s = std::sin(phi);
  if (u < sideShare) {
    const double w = u / sideShare;
    if (cylinder) {
      p = {c, w, s};
      n = {c, 0, s};
    } else { // the radius grows from the apex: density proportional to it
      const double r = std::sqrt(w);
      p = {r * c, 1 - r, r * s};
      n = Vec3(c, 1, s) / std::sqrt(2.0);
    }
    return;
  }
  double w = (u - sideShare) / (1 - sideShare);
  bool top = false;
  if (cylinder) {
    top = w >= 0.5;
    w = top ? 2 * w - 1 : 2 * w;
  }
  const double r = std::sqrt(std::clamp(w, 0.0, 1.0));
  p = {r * c, top ? 1.0 : 0.0, r * s};
  n = {0, top ? 1.0 : -1.0, 0};
}

double Emitters::pdfArea(const Hit &hit, const Vec3 &ref) const {
  if (hit.entity >= firstEntry_.size() || firstEntry_[hit.entity] < 0) return 0;
  const size_t first = static_cast<size_t>(firstEntry_[hit.entity]);
  const Entry *entry = &entries_[first];
  if (entry->kind == Kind::Triangle || entry->csgLeaf) {
    // The entity's triangles (leaves) are consecutive entries, in order;
    // those that do not emit were left out, so look for this one from its
    // own index down.
    size_t k = std::min(first + hit.primitive, entries_.size() - 1);
    while (k > first && (entries_[k].entity != hit.entity || entries_[k].part > hit.primitive))
      --k;
    entry = &entries_[k];
    if (entry->entity != hit.entity || entry->part != hit.primitive) return 0;
    if (entry->kind == Kind::Triangle) return entry->probability / triangleArea(*entry, hit.time);
  }
  if (entry->round)
    if (const double cone = coneSize(ballAt(*entry, hit.time), ref); cone > 0)
      return conePdfArea(*entry, cone, ref, hit.p, hit.ng);
  return entry->probability * worldAreaFactor(shapeOf(*entry).placementAt(hit.time), hit.ng) /
         entry->area;
}

} // namespace lray
