// Pipeline: scene description. See pigment_uv.h.
#include "scene/pigment_uv.h"

#include "shading/pigments/pigment_context.h"

#include <type_traits>
#include <variant>

namespace lray {

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
