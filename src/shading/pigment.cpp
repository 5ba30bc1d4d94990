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

namespace {

bool readsUv(const std::vector<Pigment> &pigments, uint32_t index, int depth) {
  if (index >= pigments.size() || depth > kMaxPigmentNesting) return false;
  const Pigment &pg = pigments[index];
  return std::visit(
      [&](const auto &pattern) {
        using P = std::decay_t<decltype(pattern)>;
        if constexpr (P::kDimensions == 0) {
          return false;
        } else if (pg.map.readsUv()) {
          return true;
        } else if constexpr (requires { pattern.pigment1; }) {
          return readsUv(pigments, pattern.pigment1, depth + 1) ||
                 readsUv(pigments, pattern.pigment2, depth + 1);
        } else {
          return false;
        }
      },
      pg.pattern);
}

} // namespace

bool pigmentReadsUv(const std::vector<Pigment> &pigments, uint32_t index) {
  return readsUv(pigments, index, 0);
}

} // namespace lray
