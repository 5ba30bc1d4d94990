// Pipeline: shading. Pigment evaluation (SPEC 7): the colour of a surface
// point before lighting. One switch on Pigment::Kind, no virtual calls, no
// allocation, no Lua.
#pragma once

#include "geometry/hit.h"
#include "math/color.h"
#include "scene/scene.h"
#include "shading/texture_image.h"

#include <cstddef>
#include <cstdint>

namespace lray {

/// What pigment evaluation reads: the frame's pigment table and the decoded
/// image for each Scene::images index (nullptr where none; reads as black).
struct PigmentTable {
  const Pigment *pigments = nullptr;
  size_t count = 0;
  const TextureImage *const *images = nullptr;
  size_t imageCount = 0;
};

/// Colour of pigment `index` at a hit (each pigment applies its own texture
/// map, so a checker's sub-pigments may use different maps).
Color evaluatePigment(const PigmentTable &table, uint32_t index, const Hit &hit);

/// Which sub-pigment of a 2-D checker applies at (s, t): true = pigment1,
/// where (frac(s) > 0.5) == (frac(t) > 0.5), frac(x) = x - floor(x).
bool checker2DPicksFirst(double s, double t);

/// Which sub-pigment of a 3-D checker applies at p: true = pigment1, where
/// floor(p.x) + floor(p.y) + floor(p.z) is even.
bool checker3DPicksFirst(const Vec3 &p);

/// Marble: a = |sin(dot(p, frequency) + power * turb(p, size))|,
/// colour a * color1 + (1 - a) * color2 (p in pigment space).
Color marbleColor(const Pigment &pigment, const Vec3 &p);

/// Wood: rings about z; t = sqrt(fx * p.x^2 + fy * p.y^2) + power * turb(p, size),
/// colour as marble (a negative radicand counts as 0).
Color woodColor(const Pigment &pigment, const Vec3 &p);

} // namespace lray
