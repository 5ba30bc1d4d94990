// Every class and attribute of lua/README.md: default value, set/get and bulk set
// (parameterised over a table), reference attributes, methods.
#include "lua_fixture.h"

namespace lray::lua {
namespace {

struct AttributeCase {
  const char *object;    ///< Lua expression making a fresh object
  const char *attribute;
  const char *byDefault; ///< Lua expression for the default value
  const char *newValue;  ///< a different valid value
};

std::ostream &operator<<(std::ostream &os, const AttributeCase &c) {
  return os << c.object << "." << c.attribute;
}

class AttributeTest : public LuaFixture, public ::testing::WithParamInterface<AttributeCase> {
protected:
  // Numbers and booleans compare with ==, other values by tostring
  // (Transforms have no ==).
  bool same(const std::string &a, const std::string &b) {
    return truth(
        "(function(a, b) if type(a) == 'number' or type(a) == 'boolean' then return a == b end "
        "return tostring(a) == tostring(b) end)(" +
        a + ", " + b + ")");
  }
};

TEST_P(AttributeTest, DefaultValue) {
  const AttributeCase &c = GetParam();
  EXPECT_TRUE(same(std::string(c.object) + "." + c.attribute, c.byDefault))
      << str(std::string(c.object) + "." + c.attribute);
}

TEST_P(AttributeTest, SetThenGet) {
  const AttributeCase &c = GetParam();
  ASSERT_EQ(runLua(std::string("o = ") + c.object + "; o." + c.attribute + " = " + c.newValue), "");
  EXPECT_TRUE(same(std::string("o.") + c.attribute, c.newValue));
  EXPECT_FALSE(same(c.newValue, c.byDefault)) << "the case must change the value";
}

TEST_P(AttributeTest, BulkSetReturnsTheSameObject) {
  const AttributeCase &c = GetParam();
  ASSERT_EQ(runLua(std::string("o = ") + c.object + "; r = o { " + c.attribute + " = " +
                   c.newValue + " }"),
            "");
  EXPECT_TRUE(truth("rawequal(o, r)"));
  EXPECT_TRUE(same(std::string("o.") + c.attribute, c.newValue));
}

TEST_P(AttributeTest, WrongTypeNamesFileLineClassAndAttribute) {
  const AttributeCase &c = GetParam();
  std::string error = runLua(std::string("o = ") + c.object + "\no." + c.attribute + " = {}");
  EXPECT_EQ(error.rfind("test.lua:2: ", 0), 0u) << error;
  EXPECT_NE(error.find(std::string("attribute '") + c.attribute + "' expects "), std::string::npos)
      << error;
  EXPECT_NE(error.find(", got table"), std::string::npos) << error;
}

const AttributeCase kAttributes[] = {
    {"SceneInfo()", "image_width", "800", "640"},
    {"SceneInfo()", "image_height", "600", "480"},
    {"SceneInfo()", "frames", "1", "20"},
    {"SceneInfo()", "samples", "1", "3"},
    {"SceneInfo()", "start_clock", "0", "0.5"},
    {"SceneInfo()", "end_clock", "1", "2"},
    {"SceneInfo()", "shutter", "0", "0.5"},
    {"SceneInfo()", "motion_steps", "2", "5"},
    {"Scene()", "background_color", "black", "red"},
    {"Perspective()", "transform", "Identity()", "Translate(x)"},
    {"Perspective()", "fov", "45", "60"},
    {"Perspective()", "aspect", "1.33", "1.5"},
    {"Perspective(60)", "fov", "60", "30"},
    {"Perspective(60, 2)", "aspect", "2", "1"},
    {"Scene().camera", "fov", "45", "50"},
    {"Perspective()", "aperture", "0", "0.25"},
    {"Perspective()", "focal_distance", "1", "4"},
    {"Orthographic()", "transform", "Identity()", "Translate(x)"},
    {"Orthographic()", "width", "2", "10"},
    {"Orthographic()", "aspect", "1.33", "2"},
    {"Orthographic(5, 2)", "width", "5", "1"},
    {"Spherical()", "transform", "Identity()", "Translate(x)"},
    {"Sphere()", "transform", "Identity()", "Translate(x)"},
    {"Sphere(Translate(y))", "transform", "Translate(y)", "Scale(2)"},
    {"Cube()", "transform", "Identity()", "Translate(x)"},
    {"Cube(Scale(3))", "transform", "Scale(3)", "Translate(x)"},
    {"Cylinder()", "transform", "Identity()", "Translate(x)"},
    {"Cylinder()", "open", "false", "true"},
    {"Cone()", "transform", "Identity()", "Translate(x)"},
    {"Cone(Rotate(x, 90))", "transform", "Rotate(x, 90)", "Identity()"},
    {"Cone()", "open", "false", "true"},
    {"Plane()", "transform", "Identity()", "Translate(x)"},
    {"Plane(Translate(-y))", "transform", "Translate(-y)", "Rotate(x, 10)"},
    {"Torus()", "transform", "Identity()", "Translate(x)"},
    {"Torus()", "major", "1", "2.5"},
    {"Torus()", "minor", "0.25", "0.5"},
    {"Mesh()", "transform", "Identity()", "Translate(x)"},
    {"Mesh()", "smooth", "false", "true"},
    {"Light()", "color", "white", "red"},
    {"Light()", "rows", "1", "10"},
    {"Light()", "cols", "1", "10"},
    {"Light()", "area", "false", "true"},
    {"Light()", "transform", "Identity()", "Translate(x)"},
    {"SpotLight()", "color", "white", "red"},
    {"SpotLight()", "transform", "Identity()", "LookAt(Vector(0, 5, 0), origin, z)"},
    {"SpotLight()", "angle", "30", "10"},
    {"SpotLight()", "falloff", "45", "90"},
    {"Finish()", "ambient", "Color(0.02, 0.02, 0.02)", "grey(0.1)"},
    {"Finish()", "diffuse", "0.6", "0.9"},
    {"Finish()", "specular", "0.1", "0.5"},
    {"Finish()", "exponent", "1", "20"},
    {"Finish()", "reflection", "0", "0.5"},
    {"Finish()", "refraction", "0", "0.9"},
    {"Finish()", "refraction_index", "1", "1.5"},
    {"Finish()", "absorption", "0.5", "0.1"},
    {"Texture().finish", "diffuse", "0.6", "0.7"},
    {"Texture().pigment", "color", "white", "blue"},
    {"Sphere().texture.finish", "specular", "0.1", "0.2"},
    {"ColorPigment()", "color", "white", "red"},
    {"ColorPigment(green)", "color", "green", "red"},
    {"CheckerPigment2D().pigment1", "color", "white", "red"},
    {"CheckerPigment2D().pigment2", "color", "white", "red"},
    {"MarblePigment3D()", "color1", "black", "red"},
    {"MarblePigment3D()", "color2", "white", "red"},
    {"MarblePigment3D()", "frequency", "Vector(5, 5, 5)", "Vector(1, 2, 3)"},
    {"MarblePigment3D()", "period", "Vector(5, 5, 5)", "Vector(1, 2, 3)"},
    {"MarblePigment3D()", "power", "2", "4"},
    {"MarblePigment3D()", "size", "0.2", "0.05"},
    {"WoodPigment3D()", "color1", "black", "red"},
    {"WoodPigment3D()", "color2", "white", "red"},
    {"WoodPigment3D()", "frequency", "Vector(1024, 1024, 1024)", "Vector(1, 2, 3)"},
    {"WoodPigment3D()", "period", "Vector(1024, 1024, 1024)", "Vector(1, 2, 3)"},
    {"WoodPigment3D()", "power", "2", "4"},
    {"WoodPigment3D()", "size", "0.2", "0.05"},
    {"UVMap()", "scale_s", "1", "4"},
    {"UVMap()", "scale_t", "1", "4"},
    {"UVMap()", "translate_s", "0", "0.5"},
    {"UVMap()", "translate_t", "0", "0.5"},
    {"LinearMap()", "transform", "Identity()", "Scale(2)"},
};

INSTANTIATE_TEST_SUITE_P(AllClasses, AttributeTest, ::testing::ValuesIn(kAttributes));

struct ReferenceCase {
  const char *object;
  const char *attribute;
  const char *defaultClass; ///< class of the default object
  const char *newValue;
};

std::ostream &operator<<(std::ostream &os, const ReferenceCase &c) {
  return os << c.object << "." << c.attribute;
}

class ReferenceAttributeTest : public LuaFixture,
                               public ::testing::WithParamInterface<ReferenceCase> {};

TEST_P(ReferenceAttributeTest, DefaultIsOneStableObject) {
  const ReferenceCase &c = GetParam();
  ASSERT_EQ(runLua(std::string("o = ") + c.object), "");
  EXPECT_EQ(str(std::string("o.") + c.attribute).rfind(std::string(c.defaultClass) + ": ", 0), 0u)
      << str(std::string("o.") + c.attribute);
  EXPECT_TRUE(truth(std::string("rawequal(o.") + c.attribute + ", o." + c.attribute + ")"));
}

TEST_P(ReferenceAttributeTest, SetAndBulkSetKeepIdentity) {
  const ReferenceCase &c = GetParam();
  ASSERT_EQ(runLua(std::string("o = ") + c.object + "; v = " + c.newValue + "; o." + c.attribute +
                   " = v"),
            "");
  EXPECT_TRUE(truth(std::string("rawequal(o.") + c.attribute + ", v)"));
  ASSERT_EQ(runLua(std::string("o = ") + c.object + "; v = " + c.newValue + "; r = o { " +
                   c.attribute + " = v }"),
            "");
  EXPECT_TRUE(truth(std::string("rawequal(o.") + c.attribute + ", v) and rawequal(o, r)"));
}

TEST_P(ReferenceAttributeTest, WrongTypeIsAnError) {
  const ReferenceCase &c = GetParam();
  std::string error =
      runLua(std::string("o = ") + c.object + "\no." + c.attribute + " = Vector(1, 2, 3)");
  EXPECT_EQ(error.rfind("test.lua:2: ", 0), 0u) << error;
  EXPECT_NE(error.find(std::string("attribute '") + c.attribute + "' expects "), std::string::npos)
      << error;
  EXPECT_NE(error.find(", got Vector"), std::string::npos) << error;
}

const ReferenceCase kReferences[] = {
    {"Scene()", "camera", "Perspective", "Perspective(30)"},
    {"Sphere()", "texture", "Texture", "Texture()"},
    {"Cube()", "texture", "Texture", "Texture()"},
    {"Cylinder()", "texture", "Texture", "Texture()"},
    {"Cone()", "texture", "Texture", "Texture()"},
    {"Plane()", "texture", "Texture", "Texture()"},
    {"Torus()", "texture", "Texture", "Texture()"},
    {"Mesh()", "texture", "Texture", "Texture()"},
    {"Texture()", "finish", "Finish", "Finish()"},
    {"Texture()", "pigment", "ColorPigment", "MarblePigment3D()"},
    {"CheckerPigment2D()", "pigment1", "ColorPigment", "CheckerPigment2D()"},
    {"CheckerPigment2D()", "pigment2", "ColorPigment", "ColorPigment(red)"},
    {"CheckerPigment2D()", "texture_map", "TextureMap2D", "UVMap()"},
    {"CheckerPigment3D()", "pigment1", "ColorPigment", "WoodPigment3D()"},
    {"CheckerPigment3D()", "pigment2", "ColorPigment", "ColorPigment(red)"},
    {"CheckerPigment3D()", "texture_map", "TextureMap3D", "LinearMap()"},
    {"MarblePigment3D()", "texture_map", "TextureMap3D", "LinearMap()"},
    {"WoodPigment3D()", "texture_map", "TextureMap3D", "TextureMap3D()"},
    {"ImagePigment2D('../../scenes/texture.png')", "texture_map", "TextureMap2D", "SphericalMap()"},
    {"ImagePigment2D('../../scenes/texture.png')", "texture_map", "TextureMap2D",
     "CylindricalMap()"},
};

INSTANTIATE_TEST_SUITE_P(AllClasses, ReferenceAttributeTest, ::testing::ValuesIn(kReferences));

using ObjectModelTest = LuaFixture;

TEST_F(ObjectModelTest, BulkSyntaxOnConstructorResultsAndCopies) {
  ASSERT_EQ(runLua("c = Perspective(45) { transform = Translate(x) }\n"
                   "m = Mesh(); m2 = m:copy() { smooth = true }\n"
                   "scene_info = SceneInfo() { frames = 20 }"),
            "");
  EXPECT_EQ(str("c.transform"), str("Translate(x)"));
  EXPECT_TRUE(truth("m2.smooth and not m.smooth"));
  EXPECT_EQ(num("scene_info.frames"), 20);
}

TEST_F(ObjectModelTest, ObjectsAreSharedReferences) {
  // The same Light as in lua/README.md's two forms ("Objects and attributes"), and a texture shared
  // by two spheres.
  ASSERT_EQ(runLua("t = Texture(); a = Sphere(); b = Sphere(); a.texture = t; b.texture = t\n"
                   "t.finish.reflection = 0.5"),
            "");
  EXPECT_EQ(num("a.texture.finish.reflection"), 0.5);
  EXPECT_EQ(num("b.texture.finish.reflection"), 0.5);
  EXPECT_TRUE(truth("rawequal(a.texture, b.texture)"));
}

TEST_F(ObjectModelTest, TwoFormsOfSettingAreTheSame) {
  ASSERT_EQ(runLua("l1 = Light() { color = red, area = true }\n"
                   "l2 = Light(); l2.color = red; l2.area = true"),
            "");
  EXPECT_EQ(str("l1.color"), str("l2.color"));
  EXPECT_TRUE(truth("l1.area == l2.area"));
}

TEST_F(ObjectModelTest, MeshArraysRoundTrip) {
  ASSERT_EQ(runLua("m = Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}},\n"
                   "  normals = {{0, 0, -1}}, uvs = {{0, 0}, {1, 0}, {0, 1}},\n"
                   "  indices = {{1, 2, 3}, {{2, 2, 1}, {4, nil, 1}, {3, 3}}} }"),
            "");
  EXPECT_EQ(num("#m.vertices"), 4);
  EXPECT_EQ(num("m.vertices[4][1] + m.vertices[4][2]"), 2);
  EXPECT_EQ(num("m.normals[1][3]"), -1);
  EXPECT_EQ(num("m.uvs[3][2]"), 1);
  EXPECT_EQ(num("#m.indices"), 2);
  EXPECT_EQ(num("m.indices[1][3]"), 3);
  EXPECT_EQ(num("m.indices[2][1][3]"), 1);
  EXPECT_TRUE(truth("m.indices[2][2][2] == nil and m.indices[2][2][1] == 4"));
  EXPECT_TRUE(truth("m.indices[2][3][3] == nil and m.indices[2][3][2] == 3"));
}

TEST_F(ObjectModelTest, MeshCopySharesGeometryAndTexture) {
  ASSERT_EQ(
      runLua("m = Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, indices = {{1, 2, 3}} }\n"
             "t = m.texture; c = m:copy() { transform = Translate(x) }"),
      "");
  EXPECT_TRUE(truth("rawequal(c.texture, t)"));
  EXPECT_EQ(num("#c.vertices"), 3);
  EXPECT_EQ(str("m.transform"), str("Identity()"));
  // Changing the copy's vertices leaves the original alone (copy on write).
  ASSERT_EQ(runLua("c.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}"), "");
  EXPECT_EQ(num("m.vertices[2][1]"), 1);
  EXPECT_EQ(num("c.vertices[2][1]"), 2);
}

TEST_F(ObjectModelTest, SceneMethodsAcceptEntitiesMeshesAndLights) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Sphere()); s:add_entity(Floor())\n"
                   "s:add_entities({Cube(), Cone(), Cylinder()})\n"
                   "s:add_light(Light()); s:add_lights({Light(), Light()})"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 5u);
  EXPECT_EQ(scene.entities[0].kind(), ShapeKind::Sphere);
  EXPECT_EQ(scene.entities[1].kind(), ShapeKind::Mesh);
  EXPECT_EQ(scene.entities[2].kind(), ShapeKind::Cube);
  EXPECT_EQ(scene.entities[3].kind(), ShapeKind::Cone);
  EXPECT_EQ(scene.entities[4].kind(), ShapeKind::Cylinder);
  EXPECT_EQ(scene.lights.size(), 3u);
}

} // namespace
} // namespace lray::lua
