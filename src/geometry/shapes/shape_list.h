// Pipeline: geometry. The one list of shapes: an Entity's shape is one of
// these, and geometry/shape.cpp's visitShape is the one dispatch point that
// both backends and the shading code reach a shape's own code through.
// Adding a shape: its file in this folder, one entry here (the variant and
// ShapeKind, in the same order), one registration line in
// bindings/register_entities.cpp (README.md, "Adding a shape").
#pragma once

#include "geometry/shapes/cone.h"
#include "geometry/shapes/cube.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/mesh.h"
#include "geometry/shapes/sphere.h"

#include <cstdint>
#include <type_traits>
#include <variant>

namespace lray {

/// An entity's shape and its parameters.
using Shape = std::variant<Sphere, Cylinder, Cone, Cube, Mesh>;

/// Which alternative of Shape (its index), for code that only needs the kind.
enum class ShapeKind : uint8_t { Sphere, Cylinder, Cone, Cube, Mesh };

/// The shape of kind `kind` with its default parameters.
Shape makeShape(ShapeKind kind);

/// The Lua class name of a shape ("Sphere", ...).
const char *shapeName(const Shape &shape);

/// True for the shapes the backends' trees hold (all but Mesh, whose
/// triangles the backends intersect themselves).
template <class S> constexpr bool kAnalyticShape = !std::is_same_v<S, Mesh>;

} // namespace lray
