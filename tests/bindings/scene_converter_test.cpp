// Conversion of the Lua-side objects into the plain scene model.
#include "lua_fixture.h"
#include "geometry/csg_tree.h"
#include "shape_params.h"

namespace lray::lua {
namespace {

class SceneConverterTest : public LuaFixture {};

TEST_F(SceneConverterTest, DefaultsForAnEmptyScene) {
  ASSERT_EQ(runLua("s = Scene()"), "");
  Scene scene = convertGlobal("s");
  EXPECT_EQ(scene.background, Color(0, 0, 0));
  EXPECT_EQ(scene.camera.fov, 45);
  EXPECT_EQ(scene.camera.aspect, 1.33);
  EXPECT_TRUE(scene.camera.worldFromCamera.isIdentity());
  EXPECT_TRUE(scene.entities.empty());
  EXPECT_TRUE(scene.lights.empty());
}

TEST_F(SceneConverterTest, CameraBackgroundAndLights) {
  ASSERT_EQ(runLua("s = Scene() { background_color = blue,\n"
                   "  camera = Perspective(60, 2) { transform = Translate(-5 * z) } }\n"
                   "s:add_light(Light() { color = red, rows = 2, cols = 3, area = true,\n"
                   "  transform = Translate(y) })"),
            "");
  Scene scene = convertGlobal("s");
  EXPECT_EQ(scene.background, Color(0, 0, 1));
  EXPECT_EQ(scene.camera.fov, 60);
  EXPECT_EQ(scene.camera.aspect, 2);
  EXPECT_EQ(scene.camera.loc.str(), "test.lua:2");
  EXPECT_EQ(std::get<Light>(scene.lights[0]).loc.str(), "test.lua:3");
  EXPECT_EQ(scene.camera.worldFromCamera.applyPoint({0, 0, 0}), Vec3(0, 0, -5));
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light &light = std::get<Light>(scene.lights[0]);
  EXPECT_EQ(light.color, Color(1, 0, 0));
  EXPECT_EQ(light.rows, 2);
  EXPECT_EQ(light.cols, 3);
  EXPECT_TRUE(light.area);
  EXPECT_EQ(light.worldFromLight.applyPoint({0, 0, 0}), Vec3(0, 1, 0));
}

TEST_F(SceneConverterTest, EntitiesKeepKindTransformFlagsAndLocation) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Sphere(Translate(x)))\n"
                   "s:add_entity(Cylinder() { open = true, transform = Scale(2) })\n"
                   "s:add_entity(Cone())\n"
                   "local c = Cube()\n"
                   "s:add_entity(c)"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 4u);
  EXPECT_EQ(scene.entities[0].kind(), ShapeKind::Sphere);
  EXPECT_EQ(scene.entities[0].loc.str(), "test.lua:2");
  EXPECT_EQ(scene.entities[0].worldFromObject.applyPoint({0, 0, 0}), Vec3(1, 0, 0));
  EXPECT_EQ(scene.entities[0].worldFromObject.inverse().applyPoint({1, 0, 0}), Vec3(0, 0, 0));
  EXPECT_EQ(scene.entities[1].kind(), ShapeKind::Cylinder);
  EXPECT_TRUE(isOpen(scene.entities[1]));
  EXPECT_EQ(scene.entities[1].worldFromObject.applyPoint({1, 1, 1}), Vec3(2, 2, 2));
  EXPECT_EQ(scene.entities[2].kind(), ShapeKind::Cone);
  EXPECT_FALSE(isOpen(scene.entities[2]));
  EXPECT_EQ(scene.entities[3].kind(), ShapeKind::Cube);
  EXPECT_EQ(scene.entities[3].loc.str(), "test.lua:5"); // constructed, not added
}

TEST_F(SceneConverterTest, DefaultTextureIsSharedAndWhite) {
  ASSERT_EQ(runLua("s = Scene(); s:add_entities({Sphere(), Cube()})"), "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.entities[0].texture, 0u);
  EXPECT_EQ(scene.entities[1].texture, 0u);
  const Texture &t = scene.textures[0];
  EXPECT_EQ(t.finish.diffuse, 0.6);
  EXPECT_EQ(t.finish.ambient, Color(0.02, 0.02, 0.02));
  ASSERT_EQ(scene.pigments.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<ColorPigment>(scene.pigments[t.pigment].pattern));
  EXPECT_EQ(std::get<ColorPigment>(scene.pigments[t.pigment].pattern).color, Color(1, 1, 1));
}

TEST_F(SceneConverterTest, TexturesAreDeduplicatedByIdentityAndLaterChangesAreSeen) {
  ASSERT_EQ(runLua("s = Scene(); t = Texture(); u = Texture()\n"
                   "for i = 1, 3 do s:add_entity(Sphere() { texture = t }) end\n"
                   "s:add_entity(Cube() { texture = u })\n"
                   "t.finish.reflection = 0.75 -- after assignment\n"
                   "u.pigment = t.pigment"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.textures.size(), 2u);
  EXPECT_EQ(scene.entities[0].texture, scene.entities[2].texture);
  EXPECT_NE(scene.entities[0].texture, scene.entities[3].texture);
  EXPECT_EQ(scene.textures[scene.entities[0].texture].finish.reflection, 0.75);
  EXPECT_EQ(scene.textures[scene.entities[3].texture].finish.reflection, 0);
  // One pigment object shared by both textures: one table entry.
  EXPECT_EQ(scene.pigments.size(), 1u);
  EXPECT_EQ(scene.textures[0].pigment, scene.textures[1].pigment);
}

TEST_F(SceneConverterTest, PigmentTableIsBottomUp) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "inner = CheckerPigment3D() { pigment1 = ColorPigment(red) }\n"
                   "outer = CheckerPigment2D() { pigment1 = inner, pigment2 = ColorPigment(blue),\n"
                   "  texture_map = UVMap() { scale_s = 2, scale_t = 3, translate_s = 0.5, "
                   "translate_t = 0.25 } }\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = outer } })"),
            "");
  Scene scene = convertGlobal("s");
  const Pigment &top = scene.pigments[scene.textures[0].pigment];
  ASSERT_TRUE(std::holds_alternative<CheckerPigment2D>(top.pattern));
  const auto &topChecker = std::get<CheckerPigment2D>(top.pattern);
  EXPECT_EQ(scene.textures[0].pigment, scene.pigments.size() - 1);
  EXPECT_EQ(top.map.kind, TextureMap::Kind::UVMap);
  EXPECT_EQ(top.map.scaleS, 2);
  EXPECT_EQ(top.map.scaleT, 3);
  EXPECT_EQ(top.map.translateS, 0.5);
  EXPECT_EQ(top.map.translateT, 0.25);
  ASSERT_LT(topChecker.pigment1, scene.textures[0].pigment);
  ASSERT_LT(topChecker.pigment2, scene.textures[0].pigment);
  const Pigment &inner = scene.pigments[topChecker.pigment1];
  ASSERT_TRUE(std::holds_alternative<CheckerPigment3D>(inner.pattern));
  const auto &innerChecker = std::get<CheckerPigment3D>(inner.pattern);
  EXPECT_EQ(inner.map.kind, TextureMap::Kind::TextureMap3D);
  EXPECT_LT(innerChecker.pigment1, topChecker.pigment1);
  auto colorOf = [&](uint32_t i) {
    return std::get<ColorPigment>(scene.pigments[i].pattern).color;
  };
  EXPECT_EQ(colorOf(innerChecker.pigment1), Color(1, 0, 0));
  EXPECT_EQ(colorOf(innerChecker.pigment2), Color(1, 1, 1)); // default white
  EXPECT_EQ(colorOf(topChecker.pigment2), Color(0, 0, 1));
}

TEST_F(SceneConverterTest, NoisePigmentsAndMaps) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = MarblePigment3D() {\n"
                   "  color1 = red, power = 3, size = 0.1, texture_map = LinearMap() { transform = "
                   "Scale(2) } } } })\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = WoodPigment3D() { "
                   "period = Vector(1, 2, 3) } } })\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = CheckerPigment2D() { "
                   "texture_map = SphericalMap() } } })\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = CheckerPigment2D() { "
                   "texture_map = CylindricalMap() } } })"),
            "");
  Scene scene = convertGlobal("s");
  const Pigment &marble = scene.pigments[scene.textures[0].pigment];
  ASSERT_TRUE(std::holds_alternative<MarblePigment3D>(marble.pattern));
  const auto &m = std::get<MarblePigment3D>(marble.pattern);
  EXPECT_EQ(m.color1, Color(1, 0, 0));
  EXPECT_EQ(m.color2, Color(1, 1, 1));
  EXPECT_EQ(m.frequency, Vec3(5, 5, 5));
  EXPECT_EQ(m.power, 3);
  EXPECT_EQ(m.size, 0.1);
  EXPECT_EQ(marble.loc.str(), "test.lua:2");
  EXPECT_EQ(marble.map.loc.str(), "test.lua:3");
  EXPECT_EQ(scene.textures[0].loc.str(), "test.lua:2");
  EXPECT_EQ(marble.map.kind, TextureMap::Kind::LinearMap);
  EXPECT_EQ(marble.map.transform.applyPoint({1, 1, 1}), Vec3(2, 2, 2));
  const Pigment &wood = scene.pigments[scene.textures[1].pigment];
  ASSERT_TRUE(std::holds_alternative<WoodPigment3D>(wood.pattern));
  EXPECT_EQ(std::get<WoodPigment3D>(wood.pattern).frequency, Vec3(1, 2, 3));
  EXPECT_EQ(wood.map.kind, TextureMap::Kind::TextureMap3D);
  EXPECT_EQ(scene.pigments[scene.textures[2].pigment].map.kind, TextureMap::Kind::SphericalMap);
  EXPECT_EQ(scene.pigments[scene.textures[3].pigment].map.kind, TextureMap::Kind::CylindricalMap);
}

TEST_F(SceneConverterTest, ImagesResolveAgainstTheScriptFolderAndAreShared) {
  reset(LRAY_SOURCE_DIR "/scenes");
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = "
                   "ImagePigment2D('texture.png') } })\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = "
                   "ImagePigment2D('./texture.png') } })"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.images.size(), 1u);
  EXPECT_EQ(scene.images[0].path, std::string(LRAY_SOURCE_DIR) + "/scenes/texture.png");
  EXPECT_EQ(scene.images[0].loc.str(), "test.lua:2");
  EXPECT_EQ(scene.pigments.size(), 2u);
  ASSERT_TRUE(std::holds_alternative<ImagePigment2D>(scene.pigments[0].pattern));
  EXPECT_EQ(std::get<ImagePigment2D>(scene.pigments[0].pattern).image, 0u);
  EXPECT_EQ(std::get<ImagePigment2D>(scene.pigments[1].pattern).image, 0u);
  EXPECT_EQ(scene.pigments[0].map.kind, TextureMap::Kind::TextureMap2D);
}

TEST_F(SceneConverterTest, MeshCopiesShareOneMeshData) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "m = Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},\n"
                   "  indices = {{1, 2, 3, 4}}, smooth = true }\n"
                   "s:add_entity(m)\n"
                   "s:add_entity(m:copy() { transform = Translate(x), smooth = false })"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 2u);
  EXPECT_EQ(scene.entities[0].mesh.get(), scene.entities[1].mesh.get());
  EXPECT_TRUE(scene.entities[0].smooth);
  EXPECT_FALSE(scene.entities[1].smooth);
  EXPECT_EQ(scene.entities[1].worldFromObject.applyPoint({0, 0, 0}), Vec3(1, 0, 0));
  EXPECT_EQ(scene.entities[1].loc.str(), "test.lua:5");
  const MeshData &mesh = *scene.entities[0].mesh;
  EXPECT_EQ(mesh.triangles.size(), 2u); // the quad is fanned
  EXPECT_EQ(mesh.triangleIndices.size(), 6u);
  // Building again (next frame) reuses the cached data.
  Scene again = convertGlobal("s");
  EXPECT_EQ(again.entities[0].mesh.get(), scene.entities[0].mesh.get());
  // Reassigning vertices invalidates it.
  ASSERT_EQ(runLua("m.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}"), "");
  Scene changed = convertGlobal("s");
  EXPECT_NE(changed.entities[0].mesh.get(), scene.entities[0].mesh.get());
  EXPECT_EQ(changed.entities[0].mesh->positions[1].x, 2);
  EXPECT_EQ(changed.entities[1].mesh->positions[1].x, 1); // the copy kept its geometry
}

TEST_F(SceneConverterTest, SpotLightsKeepTheirParametersAndLocation) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_lights({Light(), SpotLight() { angle = 10, falloff = 20, color = red,\n"
                   "  transform = LookAt(Vector(0, 4, 0), origin, z) }})"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(std::get<Light>(scene.lights[0]).loc.str(), "test.lua:2");
  const SpotLight &spot = std::get<SpotLight>(scene.lights[1]);
  EXPECT_EQ(spot.angle, 10);
  EXPECT_EQ(spot.falloff, 20);
  EXPECT_EQ(spot.color, Color(1, 0, 0));
  EXPECT_EQ(spot.loc.str(), "test.lua:2");
  // LookAt aims local +z at the target.
  Vec3 axis = spot.worldFromLight.applyVector({0, 0, 1});
  EXPECT_NEAR(axis.y, -1, 1e-12);
}

TEST_F(SceneConverterTest, SpotLightFalloffBelowItsAngleIsAnErrorAtItsLine) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "l = SpotLight() { angle = 40 }\n"
                   "l.falloff = 20\n"
                   "s:add_light(l)"),
            "");
  EXPECT_EQ(conversionError("s"),
            "test.lua:2: SpotLight: falloff (20) must be at least angle (40)");
}

TEST_F(SceneConverterTest, APigmentContainingItselfIsAnError) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "p = CheckerPigment2D()\n"
                   "p.pigment2 = p\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = p } })"),
            "");
  EXPECT_EQ(conversionError("s"), "test.lua:2: CheckerPigment2D: the pigment contains itself");
}

TEST_F(SceneConverterTest, PigmentsNestedTooDeepAreAnErrorNotAStackOverflow) {
  // 100,000 levels used to overflow the converter's recursion.
  ASSERT_EQ(runLua("p = ColorPigment(red)\n"
                   "for i = 1, 100000 do p = CheckerPigment2D() { pigment1 = p } end\n"
                   "s = Scene()\n"
                   "s:add_entity(Sphere() { texture = Texture() { pigment = p } })"),
            "");
  EXPECT_EQ(conversionError("s"),
            "test.lua:2: CheckerPigment2D: pigments are nested more than 64 deep");
  // 64 levels are fine.
  ASSERT_EQ(runLua("q = ColorPigment(red)\n"
                   "for i = 1, 64 do q = CheckerPigment3D() { pigment2 = q } end\n"
                   "t = Scene()\n"
                   "t:add_entity(Sphere() { texture = Texture() { pigment = q } })"),
            "");
  EXPECT_EQ(convertGlobal("t").pigments.size(), 64u + 2u);
}

TEST_F(SceneConverterTest, OnlyEntitiesWhosePigmentsReadUvGetThem) {
  ASSERT_EQ(runLua("uv = CheckerPigment2D() { pigment1 = ColorPigment(red) }\n"
                   "function with(p) return Texture() { pigment = p } end\n"
                   "s = Scene()\n"
                   "s:add_entity(Sphere())\n"
                   "s:add_entity(Sphere() { texture = with(ColorPigment(red)) })\n"
                   "s:add_entity(Torus() { texture = with(uv) })\n"
                   "s:add_entity(Cone() { texture = with(\n"
                   "  CheckerPigment3D() { pigment1 = ColorPigment(red) }) })\n"
                   "s:add_entity(Cone() { texture = with(CheckerPigment2D() {\n"
                   "  pigment1 = ColorPigment(red), texture_map = UVMap() }) })\n"
                   "s:add_entity(Sphere() { texture = with(CheckerPigment3D() {\n"
                   "  pigment2 = uv, texture_map = LinearMap() }) })\n"
                   "s:add_entity(Sphere() { texture = with(MarblePigment3D()) })\n"
                   "s:add_entity(Sphere() { texture = with(CheckerPigment2D() {\n"
                   "  pigment1 = ColorPigment(red), texture_map = SphericalMap() }) })"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 8u);
  EXPECT_FALSE(scene.entities[0].readsUv); // the default texture: white
  EXPECT_FALSE(scene.entities[1].readsUv);
  EXPECT_TRUE(scene.entities[2].readsUv);  // a 2-D pattern's default map is the (u, v)
  EXPECT_FALSE(scene.entities[3].readsUv); // a 3-D one's is the object-space point
  EXPECT_TRUE(scene.entities[4].readsUv);
  EXPECT_TRUE(scene.entities[5].readsUv);  // a sub-pigment reads them
  EXPECT_FALSE(scene.entities[6].readsUv);
  EXPECT_FALSE(scene.entities[7].readsUv); // the map's own angles from the point
}

TEST_F(SceneConverterTest, ACsgLeafReadsTheUvOfTheTextureItInherits) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "s:add_entity(Difference { Sphere(), Cube() } { texture = Texture() {\n"
                   "  pigment = CheckerPigment2D() { pigment1 = ColorPigment(red) } } })\n"
                   "s:add_entity(Union { Sphere() } { texture = Texture() {\n"
                   "  pigment = CheckerPigment2D() { pigment1 = ColorPigment(red) } } })"),
            "");
  Scene scene = convertGlobal("s");
  ASSERT_EQ(scene.entities.size(), 2u);
  for (const Entity &e : scene.entities) {
    const auto *csg = std::get_if<Csg>(&e.shape);
    ASSERT_TRUE(csg && csg->tree);
    for (const auto &leaf : csg->tree->leaves) EXPECT_TRUE(leaf.entity.readsUv);
  }
}

} // namespace
} // namespace lray::lua
