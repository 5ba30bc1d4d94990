// Vector, Color, Transform and the prelude's values (lua/README.md, "Values").
#include "lua_fixture.h"

namespace lray::lua {
namespace {

using VectorTest = LuaFixture;
using ColorTest = LuaFixture;
using TransformTest = LuaFixture;
using PreludeTest = LuaFixture;

TEST_F(VectorTest, FieldsAndToString) {
  EXPECT_EQ(num("Vector(1, 2, 3).x"), 1);
  EXPECT_EQ(num("Vector(1, 2, 3).y"), 2);
  EXPECT_EQ(num("Vector(1, 2, 3).z"), 3);
  EXPECT_EQ(str("Vector(1, 2.5, -3)"), "Vector(1, 2.5, -3)");
}

TEST_F(VectorTest, Operators) {
  EXPECT_EQ(str("Vector(1, 2, 3) + Vector(1, 1, 1)"), "Vector(2, 3, 4)");
  EXPECT_EQ(str("Vector(1, 2, 3) - Vector(1, 1, 1)"), "Vector(0, 1, 2)");
  EXPECT_EQ(str("-Vector(1, 2, 3)"), "Vector(-1, -2, -3)");
  EXPECT_EQ(str("Vector(1, 2, 3) * 2"), "Vector(2, 4, 6)");
  EXPECT_EQ(str("2 * Vector(1, 2, 3)"), "Vector(2, 4, 6)");
  EXPECT_EQ(str("Vector(2, 4, 6) / 2"), "Vector(1, 2, 3)");
  EXPECT_TRUE(truth("Vector(1, 2, 3) == Vector(1, 2, 3)"));
  EXPECT_FALSE(truth("Vector(1, 2, 3) == Vector(1, 2, 4)"));
  EXPECT_FALSE(truth("Vector(1, 2, 3) == Color(1, 2, 3)"));
}

TEST_F(VectorTest, Methods) {
  EXPECT_EQ(num("Vector(1, 2, 3):dot(Vector(4, 5, 6))"), 32);
  EXPECT_EQ(str("x:cross(y)"), "Vector(0, 0, 1)");
  EXPECT_EQ(num("Vector(3, 4, 0):length()"), 5);
  EXPECT_EQ(str("Vector(0, 0, 5):normalized()"), "Vector(0, 0, 1)");
}

TEST_F(VectorTest, Errors) {
  EXPECT_EQ(runLua("local v = Vector(1, 2, 3) * Vector(1, 2, 3)"),
            "test.lua:1: Vector: '*' multiplies a Vector by a number, got Vector * Vector (use "
            "v:dot(w) or v:cross(w))");
  EXPECT_EQ(runLua("local v = Vector(1, 2, 3) / 0"), "test.lua:1: Vector: division by zero");
  EXPECT_EQ(runLua("\nlocal v = Vector(1, 'a', 3)"),
            "test.lua:2: Vector: argument 2 expects a number, got string");
  EXPECT_EQ(runLua("local v = Vector(1, 2)"),
            "test.lua:1: Vector: argument 3 expects a number, got no value");
  EXPECT_EQ(runLua("x.x = 5"), "test.lua:1: Vector: attribute 'x' is read-only");
  EXPECT_EQ(runLua("local n = Vector(0, 0, 0):normalized()"),
            "test.lua:1: Vector:normalized: the vector has zero length");
  EXPECT_EQ(runLua("local d = Vector(1, 2, 3):dot(4)"),
            "test.lua:1: Vector:dot: argument 1 expects a Vector, got number");
  EXPECT_EQ(runLua("local d = Vector(1, 2, 3).dot(4, x)"),
            "test.lua:1: Vector:dot: self expects a Vector, got number (call methods with ':')");
  EXPECT_EQ(runLua("local v = Vector(1, 2, 3).w"), "test.lua:1: Vector: unknown attribute 'w'");
}

TEST_F(ColorTest, FieldsOperatorsAndToString) {
  EXPECT_EQ(num("Color(0.25, 0.5, 1).r"), 0.25);
  EXPECT_EQ(num("Color(0.25, 0.5, 1).g"), 0.5);
  EXPECT_EQ(num("Color(0.25, 0.5, 1).b"), 1);
  EXPECT_EQ(str("Color(0.25, 0.5, 1) + Color(0.25, 0.5, 0)"), "Color(0.5, 1, 1)");
  EXPECT_EQ(str("Color(0.25, 0.5, 1) * 2"), "Color(0.5, 1, 2)");
  EXPECT_EQ(str("2 * Color(0.25, 0.5, 1)"), "Color(0.5, 1, 2)");
  EXPECT_EQ(str("Color(0.25, 0.5, 1) * Color(2, 0.5, 0)"), "Color(0.5, 0.25, 0)");
  EXPECT_TRUE(truth("Color(1, 0, 0) == red"));
  EXPECT_EQ(runLua("local c = Color(1, 0, 0) * x"),
            "test.lua:1: Color: '*' multiplies a Color by a number or a Color, got Color * Vector");
  EXPECT_EQ(runLua("red.r = 0"), "test.lua:1: Color: attribute 'r' is read-only");
}

TEST_F(TransformTest, Factories) {
  EXPECT_EQ(str("Translate(Vector(1, 2, 3))"), "Transform([1 0 0 1], [0 1 0 2], [0 0 1 3])");
  EXPECT_EQ(str("Scale(2, 3, 4)"), "Transform([2 0 0 0], [0 3 0 0], [0 0 4 0])");
  EXPECT_EQ(str("Scale(2)"), "Transform([2 0 0 0], [0 2 0 0], [0 0 2 0])");
  EXPECT_EQ(str("Identity()"), "Transform([1 0 0 0], [0 1 0 0], [0 0 1 0])");
  // Rotate(y, 90) takes +x to -z; Rotate(z, 90) takes +x to +y.
  EXPECT_EQ(str("Rotate(y, 90)"), "Transform([0 0 1 0], [0 1 0 0], [-1 0 0 0])");
  EXPECT_EQ(str("Rotate(z, 90)"), "Transform([0 -1 0 0], [1 0 0 0], [0 0 1 0])");
  EXPECT_EQ(str("LookAt(Vector(0, 0, -5), origin, y)"),
            "Transform([1 0 0 0], [0 1 0 0], [0 0 1 -5])");
}

TEST_F(TransformTest, ProductAppliesRightFirstAndInverse) {
  // Translate then scale: (1,0,0) -> (2,0,0) -> (4,0,0).
  EXPECT_EQ(str("Scale(2) * Translate(x)"), "Transform([2 0 0 2], [0 2 0 0], [0 0 2 0])");
  EXPECT_EQ(str("Translate(x) * Scale(2)"), "Transform([2 0 0 1], [0 2 0 0], [0 0 2 0])");
  EXPECT_EQ(str("(Translate(x) * Scale(2)):inverse()"),
            "Transform([0.5 0 0 -0.5], [0 0.5 0 0], [0 0 0.5 0])");
}

TEST_F(TransformTest, Equality) {
  EXPECT_TRUE(truth("Translate(x) * Scale(2) == Translate(x) * Scale(2)"));
  EXPECT_FALSE(truth("Translate(x) * Scale(2) == Scale(2) * Translate(x)"));
  EXPECT_TRUE(truth("Scale(2) * Scale(2):inverse() == Identity()"));
}

TEST_F(TransformTest, Errors) {
  EXPECT_EQ(runLua("local a = 1\nlocal t = Scale(0, 1, 1)"),
            "test.lua:2: Scale: the transform is singular (a scale factor is zero)");
  EXPECT_EQ(runLua("local t = Scale(1, 2)"),
            "test.lua:1: Scale: takes one number (uniform) or three (sx, sy, sz)");
  EXPECT_EQ(runLua("local t = LookAt(origin, Vector(0, 5, 0), y)"),
            "test.lua:1: LookAt: up is parallel to at - pos (or at equals pos)");
  EXPECT_EQ(runLua("local t = Rotate(origin, 45)"), "test.lua:1: Rotate: the axis has zero length");
  EXPECT_EQ(runLua("local t = Translate(1, 2, 3)"),
            "test.lua:1: Translate: too many arguments (takes at most 1, got 3)");
  EXPECT_EQ(runLua("local t = Translate(x) * 2"),
            "test.lua:1: Transform __mul: argument 2 expects a Transform, got number");
}

TEST_F(PreludeTest, Globals) {
  EXPECT_EQ(str("x"), "Vector(1, 0, 0)");
  EXPECT_EQ(str("y"), "Vector(0, 1, 0)");
  EXPECT_EQ(str("z"), "Vector(0, 0, 1)");
  EXPECT_EQ(str("origin"), "Vector(0, 0, 0)");
  EXPECT_EQ(str("black"), "Color(0, 0, 0)");
  EXPECT_EQ(str("white"), "Color(1, 1, 1)");
  EXPECT_EQ(str("red"), "Color(1, 0, 0)");
  EXPECT_EQ(str("green"), "Color(0, 1, 0)");
  EXPECT_EQ(str("blue"), "Color(0, 0, 1)");
  EXPECT_EQ(str("grey(0.5)"), "Color(0.5, 0.5, 0.5)");
}

TEST_F(PreludeTest, FloorIsA200SquareWithUvsToPlusMinus25) {
  ASSERT_EQ(runLua("s = Scene(); s:add_entity(Floor())"), "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 1u);
  const Entity &floor = scene.entities[0];
  EXPECT_EQ(floor.kind(), ShapeKind::Mesh);
  EXPECT_EQ(floor.loc.str(), "test.lua:1"); // the caller's line, not the prelude's
  const MeshData &mesh = *floor.mesh;
  ASSERT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_TRUE(mesh.hasUvs);
  EXPECT_FALSE(mesh.hasNormals);
  for (const Vec3f &p : mesh.positions) {
    EXPECT_EQ(p.y, 0);
    EXPECT_EQ(std::fabs(p.x), 100);
    EXPECT_EQ(std::fabs(p.z), 100);
  }
  for (const Vec2f &uv : mesh.uvs) {
    EXPECT_EQ(std::fabs(uv.u), 25);
    EXPECT_EQ(std::fabs(uv.v), 25);
  }
  // Faces up (+y).
  for (const Vec3f &n : mesh.normals) EXPECT_NEAR(n.y, 1, 1e-6);
}

} // namespace
} // namespace lray::lua
