// The CSG classes from Lua (bindings/register_csg.cpp) and their
// conversion (scene_converter.cpp): constructors with solids and
// attributes, nesting, children, texture inheritance and its space, the
// flattening of top-level Unions, and the errors.
#include "lua_fixture.h"

#include "geometry/csg_tree.h"
#include "geometry/shape.h"

namespace lray::lua {
namespace {

class CsgBindingTest : public LuaFixture {
protected:
  static const CsgTree &treeOf(const Entity &e) { return *std::get<Csg>(e.shape).tree; }
};

TEST_F(CsgBindingTest, ConstructorsTakeSolidsAndAttributes) {
  ASSERT_EQ(
      runLua(
          "t = Texture()\n"
          "d = Difference { Cube(), Sphere(Scale(0.6)), texture = t, transform = Translate(y) }\n"
          "n = #d.children\n"
          "same = d.children[2] == d.children[2] and d.texture == t\n"
          "kids = d.children; kids[1] = nil; still = #d.children\n"
          "m = Merge { Sphere() } ; i = Intersection { d, m } ; u = Union { i, Torus() }"),
      "");
  EXPECT_EQ(num("n"), 2);
  EXPECT_EQ(str("same"), "true");
  EXPECT_EQ(num("still"), 2);
  EXPECT_EQ(str("tostring(d):match('^Difference')"), "Difference");
  EXPECT_EQ(str("tostring(u):match('^Union')"), "Union");
}

TEST_F(CsgBindingTest, NestedTreeConvertsWithComposedTransformsAndBounds) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Intersection {\n"
                   "  Difference { Cube(Scale(2)), Sphere(Translate(x)) },\n"
                   "  Sphere(Scale(1.2)),\n"
                   "  transform = Translate(Vector(0, 5, 0)),\n"
                   "})"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 1u);
  const Entity &e = scene.entities[0];
  ASSERT_EQ(e.kind(), ShapeKind::Csg);
  EXPECT_EQ(e.loc.str(), "test.lua:2");
  EXPECT_STREQ(shapeName(e.shape), "Intersection");
  const CsgTree &t = treeOf(e);
  ASSERT_EQ(t.nodes.size(), 2u);
  ASSERT_EQ(t.leaves.size(), 3u);
  EXPECT_EQ(t.nodes[1].op, CsgOp::Difference);
  // The sphere subtracted inside the Difference is inverted; the others not.
  EXPECT_FALSE(t.leaves[0].inverted);
  EXPECT_TRUE(t.leaves[1].inverted);
  EXPECT_FALSE(t.leaves[2].inverted);
  EXPECT_EQ(t.leaves[1].entity.worldFromObject.applyPoint({0, 0, 0}), Vec3(1, 5, 0));
  EXPECT_EQ(t.leaves[1].entity.loc.str(), "test.lua:3");
  // Bounds: the cube (side 2) cut to the sphere of radius 1.2, at y = 5.
  Bounds3 b = shapeWorldBounds(e);
  EXPECT_NEAR(b.lo.x, -1, 1e-9);
  EXPECT_NEAR(b.hi.y, 6, 1e-9);
  // A ray from above finds the top face of the cube at y = 6.
  Hit h;
  ASSERT_TRUE(intersectShape(e, 0, Ray{{-0.5, 10, 0}, {0, -1, 0}, 0, 1e30}, h));
  EXPECT_NEAR(h.t, 4, 1e-12);
  EXPECT_EQ(h.primitive, 0u);
}

TEST_F(CsgBindingTest, TexturesAreInheritedFromTheNearestNodeInItsSpace) {
  ASSERT_EQ(runLua("own = Texture() ; outer = Texture() ; inner = Texture()\n"
                   "s = Scene()\n"
                   "s:add_entity(Difference {\n"
                   "  Cube() { texture = own },\n"
                   "  Merge { Sphere(), Cone(), texture = inner, transform = Translate(y) },\n"
                   "  Cylinder(),\n"
                   "  texture = outer, transform = Scale(3),\n"
                   "})\n"
                   "s:add_entity(Merge { Sphere(), Cube() })"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 2u);
  const CsgTree &t = treeOf(scene.entities[0]);
  ASSERT_EQ(t.leaves.size(), 4u);
  const uint32_t own = t.leaves[0].entity.texture, inner = t.leaves[1].entity.texture,
                 outer = t.leaves[3].entity.texture;
  EXPECT_NE(own, inner);
  EXPECT_NE(own, outer);
  EXPECT_NE(inner, outer);
  EXPECT_EQ(t.leaves[2].entity.texture, inner);
  EXPECT_FALSE(t.leaves[0].inheritsTexture);
  ASSERT_TRUE(t.leaves[1].inheritsTexture);
  ASSERT_TRUE(t.leaves[3].inheritsTexture);
  // The pigment space is the node's that set the texture.
  EXPECT_EQ(t.leaves[1].textureSpace.applyPoint({0, 0, 0}), Vec3(0, 3, 0));
  EXPECT_EQ(t.leaves[3].textureSpace.applyPoint({1, 0, 0}), Vec3(3, 0, 0));
  // A hit on the carved cylinder (its base, seen from the cube's material
  // below) reports its texture point in the Difference's space (scaled by
  // 3): the world point / 3.
  Hit h;
  ASSERT_TRUE(intersectShape(scene.entities[0], 0, Ray{{0.9, -0.6, 0.3}, {0, 1, 0}, 0, 1e30}, h));
  EXPECT_EQ(h.primitive, 3u);
  EXPECT_NEAR(h.t, 0.6, 1e-12);
  EXPECT_NEAR(h.ng.y, 1, 1e-12); // out of the material, into the hole (along the ray)
  EXPECT_NEAR(h.pObject.x, h.p.x / 3, 1e-12);
  EXPECT_NEAR(h.pObject.y, h.p.y / 3, 1e-12);
  // Without any texture above: the default, not inherited.
  const CsgTree &plain = treeOf(scene.entities[1]);
  EXPECT_FALSE(plain.leaves[0].inheritsTexture);
  EXPECT_EQ(plain.leaves[0].entity.texture, plain.leaves[1].entity.texture);
}

TEST_F(CsgBindingTest, TopLevelUnionIsItsChildrenAsEntities) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "t = Texture()\n"
                   "s:add_entity(Union {\n"
                   "  Sphere() { texture = t },\n"
                   "  Union { Cube(), Cone() },\n"
                   "  Difference { Cube(), Sphere() },\n"
                   "  transform = Translate(x),\n"
                   "})\n"
                   "s:add_entity(Union { Sphere(), Torus(), texture = t })"),
            "");
  Scene scene = convertGlobal("s");
  // Sphere, Cube, Cone, the Difference, then the textured Union's two
  // solids as one-leaf CSG entities (their pigment lives in its space).
  ASSERT_EQ(scene.entities.size(), 6u);
  EXPECT_EQ(scene.entities[0].kind(), ShapeKind::Sphere);
  EXPECT_EQ(scene.entities[1].kind(), ShapeKind::Cube);
  EXPECT_EQ(scene.entities[2].kind(), ShapeKind::Cone);
  EXPECT_EQ(scene.entities[3].kind(), ShapeKind::Csg);
  EXPECT_EQ(scene.entities[1].worldFromObject.applyPoint({0, 0, 0}), Vec3(1, 0, 0));
  EXPECT_EQ(scene.entities[0].loc.str(), "test.lua:4");
  EXPECT_EQ(scene.entities[4].kind(), ShapeKind::Csg);
  EXPECT_TRUE(treeOf(scene.entities[4]).leaves[0].inheritsTexture);
  EXPECT_EQ(treeOf(scene.entities[5]).leaves[0].entity.kind(), ShapeKind::Torus);
}

TEST_F(CsgBindingTest, ErrorsNameTheLineAndTheEntry) {
  EXPECT_EQ(runLua("u = Union {}"),
            "test.lua:1: Union: the list of solids is empty (it needs at least one, as in "
            "Union { a, b })");
  EXPECT_EQ(runLua("u = Merge(Sphere(), Cube())"),
            "test.lua:1: Merge: expects one table listing its solids, as in Merge { a, b, "
            "texture = t }, got 2 arguments");
  EXPECT_EQ(runLua("u = Difference { Sphere(), 3 }"),
            "test.lua:1: Difference: entry 2 expects a solid (Sphere, Cylinder, Cone, Cube, "
            "Plane, Torus, Union, Merge, Intersection or Difference), got number");
  EXPECT_EQ(runLua("\nu = Intersection { Sphere(), Light() }"),
            "test.lua:2: Intersection: entry 2 expects a solid (Sphere, Cylinder, Cone, Cube, "
            "Plane, Torus, Union, Merge, Intersection or Difference), got Light");
  EXPECT_EQ(runLua("u = Union { Mesh() }"),
            "test.lua:1: Union: entry 1 is a Mesh, which CSG does not take: it expects a solid "
            "(Sphere, Cylinder, Cone, Cube, Plane, Torus, Union, Merge, Intersection or "
            "Difference)");
  EXPECT_EQ(runLua("u = Merge { Cylinder() { open = true } }"),
            "test.lua:1: Merge: entry 1 is an open Cylinder, which has no inside (CSG needs "
            "solids: set open = false)");
  EXPECT_EQ(runLua("u = Merge { Sphere(), nil, Cube() }"),
            "test.lua:1: Merge: entry 2 expects a solid (Sphere, Cylinder, Cone, Cube, Plane, "
            "Torus, Union, Merge, Intersection or Difference), got nil");
  EXPECT_EQ(runLua("u = Merge { Sphere(), [7] = Cube() }"),
            "test.lua:1: Merge: its table holds solids listed from 1 on and attributes by "
            "name; key 7 is neither (a nil in the list of solids?)");
  EXPECT_EQ(runLua("u = Merge { Sphere(), texure = Texture() }"),
            "test.lua:1: Merge: unknown attribute 'texure' (did you mean 'texture'?)");
  EXPECT_EQ(runLua("u = Merge { Sphere(), transform = 3 }"),
            "test.lua:1: Merge: attribute 'transform' expects a Transform, got number");
  EXPECT_EQ(runLua("u = Merge { Sphere() } ; u.children = {}"),
            "test.lua:1: Merge: attribute 'children' is read-only");
}

TEST_F(CsgBindingTest, ConversionErrorsNameTheSolidsLine) {
  // Made open after it joined the tree: found when the frame is built.
  ASSERT_EQ(runLua("s = Scene()\n"
                   "c = Cone()\n"
                   "s:add_entity(Difference { Cube(), c })\n"
                   "c.open = true"),
            "");
  EXPECT_EQ(conversionError("s"),
            "test.lua:2: Cone in a CSG: an open one has no inside (CSG needs solids: set open "
            "= false)");
  ASSERT_EQ(runLua("s = Scene()\n"
                   "u = Sphere()\n"
                   "for i = 1, 70 do u = Merge { u } end\n"
                   "s:add_entity(u)"),
            "");
  EXPECT_EQ(conversionError("s"), "test.lua:3: Merge: CSG nodes are nested more than 64 deep");
  ASSERT_EQ(runLua("s = Scene()\n"
                   "local list = {}\n"
                   "for i = 1, 5000 do list[i] = Sphere(Translate(Vector(i, 0, 0))) end\n"
                   "s:add_entity(Merge(list))"),
            "");
  EXPECT_EQ(conversionError("s").substr(0, 60),
            std::string("test.lua:4: Merge: 4097 solids in one tree, more than 4096 (each")
                .substr(0, 60));
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Difference { Cube(), Sphere(Scale(1, 1, 1)) { transform = "
                   "Scale(0, 1, 1) } })"),
            "test.lua:2: Scale: the transform is singular (a scale factor is zero)");
}

} // namespace
} // namespace lray::lua
