// Pipeline: shading. See shadow_shaft.h.
#include "shading/shadow_shaft.h"

#include "math/error_bound.h"
#include "geometry/float_frame.h"
#include "geometry/shape.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace lray {

namespace {

/// A box widened by a few ulps of its largest coordinate: the shaft test's
/// own rounding must not cut off an occluder that touches the shaft.
Bounds3 widened(const Bounds3 &b) {
  const double big = std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z),
                               std::fabs(b.hi.x), std::fabs(b.hi.y), std::fabs(b.hi.z)});
  const double pad = 16 * std::numeric_limits<double>::epsilon() * big + 1e-300;
  return {b.lo - Vec3(pad, pad, pad), b.hi + Vec3(pad, pad, pad)};
}

} // namespace

bool shaftMeetsBox(const Bounds3 &a, const Bounds3 &b, const Bounds3 &c) {
  double sLo = 0, sHi = 1;
  // On axis i the swept box spans [(1-s) a.lo + s b.lo, (1-s) a.hi + s b.hi];
  // it overlaps [c.lo, c.hi] when lo(s) <= c.hi and hi(s) >= c.lo.
  auto keep = [&](double v0, double v1, double bound, bool atMost) {
    // v(s) = v0 + s (v1 - v0) <= bound (atMost) or >= bound.
    const double slope = v1 - v0;
    const double gap = bound - v0;
    if (!atMost) {
      if (slope == 0) {
        if (v0 < bound) sHi = -1;
        return;
      }
      const double s = gap / slope;
      if (slope > 0) sLo = std::max(sLo, s);
      else sHi = std::min(sHi, s);
      return;
    }
    if (slope == 0) {
      if (v0 > bound) sHi = -1;
      return;
    }
    const double s = gap / slope;
    if (slope > 0) sHi = std::min(sHi, s);
    else sLo = std::max(sLo, s);
  };
  for (int i = 0; i < 3; ++i) {
    keep(a.lo[i], b.lo[i], c.hi[i], true);
    keep(a.hi[i], b.hi[i], c.lo[i], false);
  }
  // The rounding of s is covered by the ulps the boxes were widened by.
  return sLo <= sHi;
}

namespace {

/// Twice the float rounding of a coordinate of this magnitude, and more.
constexpr double kFloatPad = 0x1p-22;

double maxAbs(const Bounds3 &b, const Vec3 &origin) {
  return std::max(maxAbsComponent(b.lo - origin), maxAbsComponent(b.hi - origin));
}

} // namespace

ShadowShafts::ShadowShafts(const Scene &scene)
    : entities_(&scene.entities), frameOrigin_(floatFrameOrigin(scene)) {
  if (scene.entities.size() > kMaxEntities) return;
  for (uint32_t index = 0; index < scene.entities.size(); ++index) {
    const Entity &e = scene.entities[index];
    // A moving plane would need a shaft test over the shutter: none then.
    if (e.motion && std::holds_alternative<Plane>(e.shape)) return;
    if (e.isMesh()) {
      if (!e.mesh) continue; // nothing to hit
      // A moving mesh: where it may be while the shutter is open.
      const Bounds3 box = widened(meshWorldBounds(e));
      if (box.empty()) continue;
      const bool identity = e.worldFromObject.isIdentity() && !e.moves();
      meshes_.push_back({box, identity ? 0.0 : kFloatPad * maxAbs(box, frameOrigin_)});
    } else if (shapeBounded(e)) {
      const Bounds3 box = shapeWorldBounds(e);
      if (box.empty()) continue; // nothing to hit (a CSG of disjoint solids)
      boxes_.push_back(widened(box));
      boxEntity_.push_back(index);
    } else if (!std::holds_alternative<Plane>(e.shape)) {
      unboundedEntity_.push_back(index); // an unbounded CSG: a candidate for every shaft
    } else {
      planeEntity_.push_back(index);
      const Plane::WorldPlane plane = Plane::inWorld(e.worldFromObject);
      planes_.push_back({plane.normal, plane.offset,
                         e.worldFromObject.translationNorm() +
                             e.worldFromObject.inverseTranslationNorm()});
    }
  }
  enabled_ = true;
}

ShadowShafts::Candidates ShadowShafts::candidates(const Bounds3 &origins,
                                                  const Bounds3 &targets) const {
  Candidates c;
  if (!enabled_) return c;
  c.direct = true;
  auto add = [&](uint32_t entity) {
    if (c.count == kMaxDirect) c.direct = false;
    else c.entity[c.count++] = entity;
  };
  const Bounds3 a = widened(origins), b = widened(targets);
  // Meshes first: one that may block sends the batch to the backend.
  const double rayPad = kFloatPad * std::max(maxAbs(a, frameOrigin_), maxAbs(b, frameOrigin_));
  for (const MeshBox &m : meshes_) {
    const double pad = rayPad + m.ownPad;
    if (shaftMeetsBox(a, b, {m.box.lo - Vec3(pad, pad, pad), m.box.hi + Vec3(pad, pad, pad)}))
      return {};
  }
  for (size_t i = 0; i < boxes_.size() && c.direct; ++i)
    if (shaftMeetsBox(a, b, boxes_[i])) add(boxEntity_[i]);
  // A plane can block only if the shaft's corners are not all strictly on
  // one side of it (the hull of the corners is the shaft).
  for (size_t i = 0; i < planes_.size() && c.direct; ++i) {
    const HalfSpace &h = planes_[i];
    int above = 0, below = 0, on = 0;
    for (const Bounds3 *box : {&a, &b})
      for (int k = 0; k < 8; ++k) {
        const Vec3 p((k & 1) ? box->hi.x : box->lo.x, (k & 2) ? box->hi.y : box->lo.y,
                     (k & 4) ? box->hi.z : box->lo.z);
        const double d = dot(h.normal, p) - h.offset;
        const double tolerance = 64 * std::numeric_limits<double>::epsilon() *
                                 (std::fabs(h.offset) + h.magnitude + std::fabs(p.x) +
                                  std::fabs(p.y) + std::fabs(p.z));
        if (d > tolerance) ++above;
        else if (d < -tolerance) ++below;
        else ++on; // on the plane, within rounding: it may block
      }
    if (on || (above && below)) add(planeEntity_[i]);
  }
  for (size_t i = 0; i < unboundedEntity_.size() && c.direct; ++i) add(unboundedEntity_[i]);
  if (!c.direct) return {};
  c.clear = c.count == 0;
  return c;
}

void ShadowShafts::occluded(const Candidates &c, const Ray *rays, size_t n,
                            uint8_t *blocked) const {
  for (size_t base = 0; base < n; base += 4) {
    const size_t m = std::min<size_t>(4, n - base);
    uint32_t open = (1u << m) - 1; // not yet blocked
    const Ray *lane[4];
    double tMax[4];
    for (size_t k = 0; k < 4; ++k) {
      lane[k] = &rays[base + (k < m ? k : 0)]; // past n: the first ray again
      tMax[k] = lane[k]->tMax;
    }
    for (size_t i = 0; i < c.count && open != 0; ++i) {
      const Entity &entity = (*entities_)[c.entity[i]];
      if (isStillSphere(entity)) {
        open &= ~occludedStillSphereLanes(entity, lane, tMax);
        continue;
      }
      for (uint32_t left = open; left != 0; left &= left - 1) {
        const int k = std::countr_zero(left);
        if (occludedShape(entity, *lane[k])) open &= ~(1u << k);
      }
    }
    for (size_t k = 0; k < m; ++k) blocked[base + k] = (open >> k & 1u) ? 0 : 1;
  }
}

} // namespace lray
