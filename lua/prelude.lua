-- LRay prelude: run before every scene script (lua/README.md, "Prelude"). Embedded into
-- the binary at build time by bindings/sources.cmake.

-- Unit vectors and the origin.
x = Vector(1, 0, 0)
y = Vector(0, 1, 0)
z = Vector(0, 0, 1)
origin = Vector(0, 0, 0)

-- Standard colours.
black = Color(0, 0, 0)
white = Color(1, 1, 1)
red = Color(1, 0, 0)
green = Color(0, 1, 0)
blue = Color(0, 0, 1)

--- A grey of intensity a: Color(a, a, a).
function grey(a)
  return Color(a, a, a)
end

--- A 200 x 200 square at y = 0 (facing +y) with uv running from -25 to 25
--- across it, so a CheckerPigment2D gives 2-unit squares (paper, Listing 3).
--- Its arguments are Mesh's (an optional Transform), checked by Mesh.
function Floor(...)
  return Mesh(...) {
    vertices = {
      { -100.0, 0.0, -100.0 },
      { 100.0, 0.0, -100.0 },
      { 100.0, 0.0, 100.0 },
      { -100.0, 0.0, 100.0 },
    },
    uvs = {
      { -25.0, -25.0 },
      { 25.0, -25.0 },
      { 25.0, 25.0 },
      { -25.0, 25.0 },
    },
    indices = {
      { { 1, 1 }, { 4, 4 }, { 2, 2 } },
      { { 2, 2 }, { 4, 4 }, { 3, 3 } },
    },
  }
end

-- mesh_from_obj(path) is native (bindings/register_entities.cpp): large OBJ
-- files are never parsed in Lua.
