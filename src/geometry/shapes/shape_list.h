// Pipeline: geometry. The one list of shapes: an Entity's shape is one of
// these, and geometry/shape.cpp's visitShape is the one dispatch point that
// both backends and the shading code reach a shape's own code through.
// Adding a shape: its file in this folder, one entry here (the variant and
// ShapeKind, in the same order), one registration line in
// bindings/register_entities.cpp (README.md, "Adding a shape").
#pragma once

#include "geometry/shapes/cone.h"
#include "geometry/shapes/csg.h"
#include "geometry/shapes/cube.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/mesh.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "geometry/shapes/torus.h"

#include <cassert>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <variant>

namespace lray {

/// An entity's shape and its parameters.
using Shape = std::variant<Sphere, Cylinder, Cone, Cube, Mesh, Plane, Torus, Csg>;

/// Which alternative of Shape (its index), for code that only needs the kind.
enum class ShapeKind : uint8_t { Sphere, Cylinder, Cone, Cube, Mesh, Plane, Torus, Csg };

template <ShapeKind K, class S>
constexpr bool kKindIs = std::is_same_v<std::variant_alternative_t<size_t(K), Shape>, S>;
static_assert(kKindIs<ShapeKind::Sphere, Sphere> && kKindIs<ShapeKind::Cylinder, Cylinder> &&
                  kKindIs<ShapeKind::Cone, Cone> && kKindIs<ShapeKind::Cube, Cube> &&
                  kKindIs<ShapeKind::Mesh, Mesh> && kKindIs<ShapeKind::Plane, Plane> &&
                  kKindIs<ShapeKind::Torus, Torus> && kKindIs<ShapeKind::Csg, Csg> &&
                  std::variant_size_v<Shape> == size_t(ShapeKind::Csg) + 1,
              "ShapeKind lists the alternatives of Shape in order");

/// The shape of kind `kind` with its default parameters.
template <size_t... I> Shape makeShape(ShapeKind kind, std::index_sequence<I...>) {
  assert(size_t(kind) < sizeof...(I) && "makeShape: not a ShapeKind");
  Shape shape;
  ((size_t(kind) == I ? (shape.emplace<I>(), 0) : 0), ...);
  return shape;
}
inline Shape makeShape(ShapeKind kind) {
  return makeShape(kind, std::make_index_sequence<std::variant_size_v<Shape>>{});
}

/// The Lua class name of a shape ("Sphere", ...).
const char *shapeName(const Shape &shape);

/// True for the shapes the backends' trees hold (all but Mesh, whose
/// triangles the backends intersect themselves).
template <class S> constexpr bool kAnalyticShape = !std::is_same_v<S, Mesh>;

/// True for the shapes with their own object-space ray test (shapes/*.h):
/// the analytic ones but CSG, whose leaves are such shapes.
template <class S>
constexpr bool kPrimitiveShape = kAnalyticShape<S> && !std::is_same_v<S, Csg>;

/// The solids, the only shapes CSG takes (lua/README.md, "CSG"), are those
/// with an inside: S::kSolid says whether shapes of kind S have one. A kind
/// with an attribute that can take its inside away (an open Cylinder) also
/// has `const char *hollowedBy() const`: that attribute while it is set.
template <class S> constexpr bool kSolidShape = S::kSolid;

/// The attribute that leaves `shape`, of a solid kind, without an inside
/// ("open"), or null when it is a solid.
inline const char *hollowedBy(const Shape &shape) {
  return std::visit(
      [](const auto &s) -> const char * {
        using S = std::decay_t<decltype(s)>;
        static_assert(kSolidShape<S> || !requires { s.hollowedBy(); });
        if constexpr (requires { s.hollowedBy(); })
          return s.hollowedBy();
        else
          return nullptr;
      },
      shape);
}

} // namespace lray
