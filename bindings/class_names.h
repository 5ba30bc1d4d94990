// Pipeline: script -> scene description. Lists of Lua class names for
// messages ("an entity (Sphere, ... or Difference)"), derived from the
// variants the classes stand for (geometry/shapes/shape_list.h, the lights'
// variant), so a new kind shows in every message without a list of its own
// to keep up.
#pragma once

#include "geometry/shapes/shape_list.h"

#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace lray::lua {

/// "A, B or C".
inline std::string joinNames(const std::vector<std::string> &names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

/// Keeps every alternative (for classNames).
template <class> struct EveryKind : std::true_type {};
/// Keeps the solid shapes, those CSG takes (kSolidShape).
template <class S> struct SolidKind : std::bool_constant<kSolidShape<S>> {};

/// The Lua class names of the alternatives S of variant V that Keep<S>
/// keeps, in the variant's order; the CSG shape stands for its operator
/// classes (Union, Merge, Intersection and Difference).
template <class V, template <class> class Keep, size_t... I>
std::vector<std::string> classNameList(std::index_sequence<I...>) {
  std::vector<std::string> out;
  auto add = [&out]<class S>(std::type_identity<S>) {
    if constexpr (!Keep<S>::value) {
      return;
    } else if constexpr (std::is_same_v<S, Csg>) {
      for (int op = 0; op <= static_cast<int>(CsgOp::Difference); ++op)
        out.emplace_back(csgOpName(static_cast<CsgOp>(op)));
    } else {
      out.emplace_back(S::kName);
    }
  };
  (add(std::type_identity<std::variant_alternative_t<I, V>>{}), ...);
  return out;
}

/// classNameList joined: "Sphere, Cylinder, ... or Difference".
template <class V, template <class> class Keep = EveryKind> std::string classNames() {
  return joinNames(classNameList<V, Keep>(std::make_index_sequence<std::variant_size_v<V>>{}));
}

} // namespace lray::lua
