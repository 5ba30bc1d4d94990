// Pipeline: shading. What a pigment's evaluate sees: the frame's pigment
// table (for a checker's sub-pigments), the decoded images, and the texture
// map that turns the hit into the pigment's lookup point.
#pragma once

#include "math/hit.h"
#include "math/color.h"
#include "shading/pigments/texture_map.h"
#include "shading/pigments/texture_image.h"

#include <cstddef>
#include <cstdint>

namespace lray {

struct Pigment;

/// What pigment evaluation reads: the frame's pigment table and the decoded
/// image for each Scene::images index (nullptr where none; reads as black).
struct PigmentTable {
  const Pigment *pigments = nullptr;
  size_t count = 0;
  const TextureImage *const *images = nullptr;
  size_t imageCount = 0;
};

/// How deep checkers may nest: the converter refuses deeper scripts (their
/// recursion would otherwise be as deep as the user's data), so evaluation
/// never meets more.
constexpr int kMaxPigmentNesting = 64;

/// One evaluation: the table, the pigment's own map, the hit, and how deep
/// in nested checkers it is (bounded against a malformed table).
struct PigmentContext {
  const PigmentTable &table;
  const TextureMap &map;
  const Hit &hit;
  int depth;
};

/// Colour of pigment `index` of the table at a hit (each pigment applies
/// its own texture map, so a checker's sub-pigments may use different maps).
Color evaluatePigment(const PigmentTable &table, uint32_t index, const Hit &hit);

namespace pigment_detail {
/// evaluatePigment one level deeper (a checker's sub-pigment).
Color evaluateNested(const PigmentContext &c, uint32_t index);
} // namespace pigment_detail

} // namespace lray
