// Pipeline: shading. Pigment formulas of SPEC 7.
#include "shading/pigment.h"

#include "shading/perlin_noise.h"
#include "shading/texture_map.h"

#include <algorithm>
#include <cmath>

namespace lray {
namespace {

/// Checkers nest by index (children always smaller); the bound only guards
/// against a malformed table looping.
constexpr int kMaxPigmentDepth = 64;

inline Color blend(const Pigment &pigment, double t) {
  double a = std::fabs(std::sin(t));
  if (!std::isfinite(a)) a = 0;
  return pigment.color1 * a + pigment.color2 * (1 - a);
}

Color evaluate(const PigmentTable &table, uint32_t index, const Hit &hit, int depth) {
  if (index >= table.count || depth > kMaxPigmentDepth) return {};
  const Pigment &pg = table.pigments[index];
  switch (pg.kind) {
  case Pigment::Kind::Color:
    return pg.color;
  case Pigment::Kind::Checker2D: {
    TexCoord2 st = mapPoint2D(pg.map, hit);
    return evaluate(table, checker2DPicksFirst(st.s, st.t) ? pg.pigment1 : pg.pigment2, hit,
                    depth + 1);
  }
  case Pigment::Kind::Checker3D:
    return evaluate(table, checker3DPicksFirst(mapPoint3D(pg.map, hit)) ? pg.pigment1 : pg.pigment2,
                    hit, depth + 1);
  case Pigment::Kind::Marble3D:
    return marbleColor(pg, mapPoint3D(pg.map, hit));
  case Pigment::Kind::Wood3D:
    return woodColor(pg, mapPoint3D(pg.map, hit));
  case Pigment::Kind::Image2D: {
    if (pg.image >= table.imageCount || !table.images[pg.image]) return {};
    TexCoord2 st = mapPoint2D(pg.map, hit);
    return table.images[pg.image]->lookup(st.s, st.t);
  }
  }
  return {};
}

} // namespace

bool checker2DPicksFirst(double s, double t) {
  double fs = s - std::floor(s);
  double ft = t - std::floor(t);
  return (fs > 0.5) == (ft > 0.5);
}

bool checker3DPicksFirst(const Vec3 &p) {
  double sum = std::floor(p.x) + std::floor(p.y) + std::floor(p.z);
  // Parity that also holds for negative sums (fmod keeps the sign).
  return sum - 2 * std::floor(sum / 2) == 0;
}

Color marbleColor(const Pigment &pigment, const Vec3 &p) {
  return blend(pigment, dot(p, pigment.frequency) + pigment.power * turbulence(p, pigment.size));
}

Color woodColor(const Pigment &pigment, const Vec3 &p) {
  double r2 = pigment.frequency.x * p.x * p.x + pigment.frequency.y * p.y * p.y;
  return blend(pigment, std::sqrt(std::max(0.0, r2)) + pigment.power * turbulence(p, pigment.size));
}

Color evaluatePigment(const PigmentTable &table, uint32_t index, const Hit &hit) {
  return evaluate(table, index, hit, 0);
}

} // namespace lray
