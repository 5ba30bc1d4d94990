// Pipeline: shading. evaluatePigment: one std::visit on the pattern.
#include "shading/pigment.h"

namespace lray {

namespace {

Color evaluate(const PigmentTable &table, uint32_t index, const Hit &hit, int depth) {
  // Checkers nest by index (children always smaller); the bound guards
  // against a malformed table looping.
  if (index >= table.count || depth > kMaxPigmentNesting) return {};
  const Pigment &pg = table.pigments[index];
  const PigmentContext c{table, pg.map, hit, depth};
  return std::visit([&](const auto &pattern) { return pattern.evaluate(c); }, pg.pattern);
}

} // namespace

namespace pigment_detail {
Color evaluateNested(const PigmentContext &c, uint32_t index) {
  return evaluate(c.table, index, c.hit, c.depth + 1);
}
} // namespace pigment_detail

Color evaluatePigment(const PigmentTable &table, uint32_t index, const Hit &hit) {
  return evaluate(table, index, hit, 0);
}

} // namespace lray
