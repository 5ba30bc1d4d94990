// Every user error the bindings detect: the message names file:line, the
// class, the attribute, what was expected and what was given (lua/README.md, "The scene file").
#include "lua_fixture.h"

#include <chrono>

namespace lray::lua {
namespace {

using BindingErrorTest = LuaFixture;

TEST_F(BindingErrorTest, UnknownAttributeSuggestsTheClosestName) {
  EXPECT_EQ(runLua("Finish().specularity = 1"),
            "test.lua:1: Finish: unknown attribute 'specularity' (did you mean 'specular'?)");
  EXPECT_EQ(runLua("local l = Light() { colr = red }"),
            "test.lua:1: Light: unknown attribute 'colr' (did you mean 'color'?)");
  EXPECT_EQ(runLua("local a = 1\nlocal f = Finish().difuse"),
            "test.lua:2: Finish: unknown attribute 'difuse' (did you mean 'diffuse'?)");
  EXPECT_EQ(runLua("Sphere().banana = 1"), "test.lua:1: Sphere: unknown attribute 'banana'");
  EXPECT_EQ(runLua("Sphere().copy = 1"), "test.lua:1: Sphere: unknown attribute 'copy'");
  EXPECT_EQ(runLua("Mesh().copy = 1"), "test.lua:1: Mesh: cannot assign to method 'copy'");
  EXPECT_EQ(runLua("local s = Scene() { [1] = 2 }"),
            "test.lua:1: Scene: attributes are named by strings, got number");
}

TEST_F(BindingErrorTest, WrongTypeNamesExpectedAndGiven) {
  EXPECT_EQ(runLua("local f = Finish()\nf.diffuse = 'high'"),
            "test.lua:2: Finish: attribute 'diffuse' expects a number, got string");
  EXPECT_EQ(runLua("Light().color = Vector(1, 1, 1)"),
            "test.lua:1: Light: attribute 'color' expects a Color, got Vector");
  EXPECT_EQ(runLua("Light().area = 1"),
            "test.lua:1: Light: attribute 'area' expects a boolean, got number");
  EXPECT_EQ(runLua("Sphere().transform = x"),
            "test.lua:1: Sphere: attribute 'transform' expects a Transform, got Vector");
  EXPECT_EQ(runLua("Sphere().texture = Finish()"),
            "test.lua:1: Sphere: attribute 'texture' expects a Texture, got Finish");
  EXPECT_EQ(runLua("Texture().finish = nil"),
            "test.lua:1: Texture: attribute 'finish' expects a Finish, got nil");
  EXPECT_EQ(runLua("Finish().diffuse = math.huge"),
            "test.lua:1: Finish: attribute 'diffuse' expects a finite number, got inf");
  EXPECT_EQ(runLua("local s = Sphere(x)"),
            "test.lua:1: Sphere: argument 1 expects a Transform, got Vector");
  EXPECT_EQ(runLua("local s = Sphere(Identity(), 2)"),
            "test.lua:1: Sphere: too many arguments (takes at most 1, got 2)");
  EXPECT_EQ(runLua("local f = Finish() 'x'"), "test.lua:1: Finish: calling an object sets "
                                              "attributes in bulk and takes one table, got string");
}

TEST_F(BindingErrorTest, IntegerAttributesMustBePositiveIntegers) {
  EXPECT_EQ(runLua("scene_info = SceneInfo() { frames = 0 }"),
            "test.lua:1: SceneInfo: attribute 'frames' expects a positive integer, got 0");
  EXPECT_EQ(runLua("scene_info = SceneInfo() { image_width = -640 }"),
            "test.lua:1: SceneInfo: attribute 'image_width' expects a positive integer, got -640");
  EXPECT_EQ(runLua("scene_info = SceneInfo() { image_height = 2.5 }"),
            "test.lua:1: SceneInfo: attribute 'image_height' expects an integer, got 2.5");
  EXPECT_EQ(runLua("scene_info = SceneInfo() { samples = '4' }"),
            "test.lua:1: SceneInfo: attribute 'samples' expects an integer, got string");
  EXPECT_EQ(runLua("Light().rows = 0"),
            "test.lua:1: Light: attribute 'rows' expects a positive integer, got 0");
  EXPECT_EQ(runLua("Light().cols = -1"),
            "test.lua:1: Light: attribute 'cols' expects a positive integer, got -1");
  EXPECT_EQ(runLua("MarblePigment3D().size = 0"),
            "test.lua:1: MarblePigment3D: attribute 'size' expects a positive number, got 0");
  EXPECT_EQ(runLua("Torus().minor = 0"),
            "test.lua:1: Torus: attribute 'minor' expects a positive number, got 0");
  EXPECT_EQ(runLua("local t = Torus() { major = -1 }"),
            "test.lua:1: Torus: attribute 'major' expects a positive number, got -1");
  EXPECT_EQ(runLua("Torus().major = 'big'"),
            "test.lua:1: Torus: attribute 'major' expects a number, got string");
  EXPECT_EQ(runLua("Sphere().major = 1"),
            "test.lua:1: Sphere: unknown attribute 'major'");
  EXPECT_EQ(runLua("Plane().open = true"), "test.lua:1: Plane: unknown attribute 'open'");
  EXPECT_EQ(
      runLua("SpotLight().angle = -1"),
      "test.lua:1: SpotLight: attribute 'angle' expects an angle between 0 and 90 degrees, got -1");
  EXPECT_EQ(runLua("local s = SpotLight() { falloff = 91 }"),
            "test.lua:1: SpotLight: attribute 'falloff' expects an angle between 0 and 90 degrees, "
            "got 91");
  EXPECT_EQ(runLua("SpotLight().angle = 'wide'"),
            "test.lua:1: SpotLight: attribute 'angle' expects a number, got string");
  EXPECT_EQ(runLua("SpotLight().rows = 2"), "test.lua:1: SpotLight: unknown attribute 'rows'");
  EXPECT_EQ(runLua("Light().falloff = 2"), "test.lua:1: Light: unknown attribute 'falloff'");
  EXPECT_EQ(runLua("Perspective().fov = 180"), "test.lua:1: Perspective: attribute 'fov' expects "
                                               "an angle between 0 and 180 degrees, got 180");
  EXPECT_EQ(
      runLua("local c = Perspective(0)"),
      "test.lua:1: Perspective: argument 1 expects an angle between 0 and 180 degrees, got 0");
  EXPECT_EQ(runLua("Perspective().aperture = -0.1"),
            "test.lua:1: Perspective: attribute 'aperture' expects a number >= 0, got -0.1");
  EXPECT_EQ(runLua("Perspective().focal_distance = 0"),
            "test.lua:1: Perspective: attribute 'focal_distance' expects a positive number, got 0");
  EXPECT_EQ(runLua("local c = Orthographic(-2)"),
            "test.lua:1: Orthographic: argument 1 expects a positive number, got -2");
  EXPECT_EQ(runLua("local c = Orthographic(2, 0)"),
            "test.lua:1: Orthographic: argument 2 expects a positive number, got 0");
  EXPECT_EQ(runLua("Orthographic().fov = 30"), "test.lua:1: Orthographic: unknown attribute 'fov'");
  EXPECT_EQ(runLua("Spherical().aperture = 1"),
            "test.lua:1: Spherical: unknown attribute 'aperture'");
  // Floor takes Mesh's arguments, checked as Mesh checks them.
  EXPECT_EQ(runLua("local f = Floor(Translate(y))"), "");
  EXPECT_EQ(runLua("local f = Floor(3)").rfind(
                "test.lua:1: Mesh: argument 1 expects a Transform, got number", 0),
            0u);
  EXPECT_EQ(runLua("SceneInfo().shutter = 1.5"),
            "test.lua:1: SceneInfo: attribute 'shutter' expects a number between 0 and 1, got 1.5");
  EXPECT_EQ(runLua("SceneInfo().motion_steps = 1"),
            "test.lua:1: SceneInfo: attribute 'motion_steps' expects an integer from 2 to 16, "
            "got 1");
  EXPECT_EQ(runLua("SceneInfo().motion_steps = 17"),
            "test.lua:1: SceneInfo: attribute 'motion_steps' expects an integer from 2 to 16, "
            "got 17");
  // Whole numbers given as floats are accepted.
  EXPECT_EQ(runLua("scene_info = SceneInfo() { frames = 4.0 }"), "");
  EXPECT_EQ(num("scene_info.frames"), 4);
}

TEST_F(BindingErrorTest, EmissionIsAColourOfNonNegativeRadianceAndNeedsAnArea) {
  EXPECT_EQ(runLua("Finish().emission = 2"),
            "test.lua:1: Finish: attribute 'emission' expects a Color, got number");
  EXPECT_EQ(runLua("Finish().emission = Color(1, -0.5, 0)"),
            "test.lua:1: Finish: attribute 'emission' expects a colour with components >= 0, got "
            "Color");
  EXPECT_EQ(runLua("Finish().fresnel = 1"),
            "test.lua:1: Finish: attribute 'fresnel' expects a boolean, got number");
  EXPECT_EQ(runLua("local f = Finish()\nf.roughness = 1.5"),
            "test.lua:2: Finish: attribute 'roughness' expects a number between 0 and 1, got "
            "1.5");
  EXPECT_EQ(runLua("Finish() { roughness = -0.1 }"),
            "test.lua:1: Finish: attribute 'roughness' expects a number between 0 and 1, got "
            "-0.1");
  EXPECT_EQ(runLua("Finish().roughness = 'rough'"),
            "test.lua:1: Finish: attribute 'roughness' expects a number, got string");
  ASSERT_EQ(runLua("lamp = Texture() { finish = Finish() { emission = white } }\n"
                   "s = Scene()\n"
                   "s:add_entity(Sphere() { texture = lamp })\n"
                   "s:add_entity(Plane() { texture = lamp })\n"
                   "t = Scene()\n"
                   "t:add_entity(Difference {\n"
                   "  Sphere() { texture = lamp }, Plane() { texture = lamp } })\n"
                   "u = Scene()\n"
                   "u:add_entity(Sphere() { texture = lamp })\n"),
            "");
  EXPECT_EQ(conversionError("s"), "test.lua:4: Plane: its finish emits (emission), but a plane "
                                  "has no finite area to emit from");
  EXPECT_EQ(conversionError("t"), "test.lua:7: Plane: its finish emits (emission), but a plane "
                                  "has no finite area to emit from");
  EXPECT_EQ(conversionError("u"), "no error");
}

TEST_F(BindingErrorTest, TheIntegratorIsNamedAndItsDepthPositive) {
  EXPECT_EQ(runLua("SceneInfo().integrator = 'pathtracer'"),
            "test.lua:1: SceneInfo: attribute 'integrator' expects \"whitted\" or \"path\", got "
            "'pathtracer'");
  EXPECT_EQ(runLua("SceneInfo().integrator = 1"),
            "test.lua:1: SceneInfo: attribute 'integrator' expects a string, got number");
  EXPECT_EQ(runLua("SceneInfo().max_depth = 0"),
            "test.lua:1: SceneInfo: attribute 'max_depth' expects a positive integer, got 0");
  EXPECT_EQ(runLua("SceneInfo() { integrator = 'path', max_depth = 3 }"), "");
}

TEST_F(BindingErrorTest, TextureMapsMustMatchThePigmentDimension) {
  EXPECT_EQ(runLua("CheckerPigment2D().texture_map = LinearMap()"),
            "test.lua:1: CheckerPigment2D: attribute 'texture_map' expects a 2-D texture map "
            "(TextureMap2D, UVMap, SphericalMap or CylindricalMap), got LinearMap");
  EXPECT_EQ(runLua("MarblePigment3D().texture_map = UVMap()"),
            "test.lua:1: MarblePigment3D: attribute 'texture_map' expects a 3-D texture map "
            "(TextureMap3D or LinearMap), got UVMap");
  EXPECT_EQ(runLua("Texture().pigment = Finish()").rfind(
                "test.lua:1: Texture: attribute 'pigment' expects a pigment (ColorPigment, ", 0),
            0u);
  EXPECT_EQ(runLua("ColorPigment().pigment1 = ColorPigment()"),
            "test.lua:1: ColorPigment: unknown attribute 'pigment1'");
}

TEST_F(BindingErrorTest, MissingImageNamesThePath) {
  std::string error = runLua("local p = ImagePigment2D('no_such_image.png')");
  EXPECT_EQ(
      error.rfind("test.lua:1: ImagePigment2D: cannot read image 'no_such_image.png' (looked for /",
                  0),
      0u)
      << error;
  EXPECT_EQ(runLua("local p = ImagePigment2D()"),
            "test.lua:1: ImagePigment2D: argument 1 expects a string, got no value");
}

TEST_F(BindingErrorTest, MalformedMeshDataNamesTheEntryOrFace) {
  EXPECT_EQ(runLua("Mesh().vertices = {{0, 0, 0}, {1, 0}}"),
            "test.lua:1: Mesh: attribute 'vertices' expects a list of {x, y, z}, entry 2 is a "
            "table of 2 values");
  EXPECT_EQ(runLua("Mesh().vertices = {{0, 0, 0}, {1, 0, 0/0}}").rfind(
                "test.lua:1: Mesh: attribute 'vertices' expects a list of {x, y, z}, entry 2 is a "
                "table holding the non-finite number ", 0),
            0u);
  EXPECT_EQ(
      runLua("Mesh().vertices = {{0, 0, 0}, {1, 0, math.huge}}"),
      "test.lua:1: Mesh: attribute 'vertices' expects a list of {x, y, z}, entry 2 is a table "
      "holding the non-finite number inf");
  // Finite as a double but not as the float the mesh is stored in.
  EXPECT_EQ(runLua("Mesh().normals = {{0, 1e39, 0}}"),
            "test.lua:1: Mesh: attribute 'normals' expects a list of {x, y, z}, entry 1 is a table "
            "holding 1e+39, out of range for single precision");
  EXPECT_EQ(runLua("Mesh().uvs = {{0, 0}, 'a'}"),
            "test.lua:1: Mesh: attribute 'uvs' expects a list of {u, v}, entry 2 is string");
  EXPECT_EQ(runLua("Mesh().normals = 3"),
            "test.lua:1: Mesh: attribute 'normals' expects a list of {x, y, z}, got number");
  EXPECT_EQ(runLua("Mesh().indices = {{1, 2, 3}, {1, 2}}"),
            "test.lua:1: Mesh: attribute 'indices': face 2 has 2 corners, needs at least 3");
  EXPECT_EQ(runLua("Mesh().indices = {{1, 2, 3}, {1, 'b', 3}}"),
            "test.lua:1: Mesh: attribute 'indices': face 2, corner 2 must be an index or {v, uv, "
            "n}, got string");
  EXPECT_EQ(
      runLua("Mesh().indices = {{1, 2, 0}}"),
      "test.lua:1: Mesh: attribute 'indices': face 1, corner 3: vertex index must be a positive "
      "integer, got 0");
  EXPECT_EQ(runLua("Mesh().indices = {{1, 2, {3, 1.5}}}"),
            "test.lua:1: Mesh: attribute 'indices': face 1, corner 3: uv index must be a positive "
            "integer, got 1.5");
  EXPECT_EQ(
      runLua("Mesh().indices = {{1, 2, {3, 1, 1, 1}}}"),
      "test.lua:1: Mesh: attribute 'indices': face 1, corner 3 has more than 3 entries {v, uv, n}");
}

TEST_F(BindingErrorTest, OutOfRangeMeshIndexNamesTheMeshLineAndFace) {
  ASSERT_EQ(runLua("s = Scene()\n"
                   "m = Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},\n"
                   "  indices = {{1, 2, 3}, {1, 3, 4}} }\n"
                   "s:add_entity(m)"),
            "");
  try {
    convertGlobal("s");
    FAIL() << "expected a SceneError";
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(),
                 "test.lua:2: Mesh: face 2, corner 3: vertex index 4 is out of range (3 vertices)");
  }
  ASSERT_EQ(
      runLua("s = Scene(); s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},\n"
             "  uvs = {{0, 0}}, indices = {{{1, 1}, {2, 2}, {3, 1}}} })"),
      "");
  try {
    convertGlobal("s");
    FAIL() << "expected a SceneError";
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(),
                 "test.lua:1: Mesh: face 1, corner 2: uv index 2 is out of range (1 uvs)");
  }
  ASSERT_EQ(runLua("s = Scene()\ns:add_entity(Mesh())"), "");
  try {
    convertGlobal("s");
    FAIL() << "expected a SceneError";
  } catch (const SceneError &e) {
    EXPECT_STREQ(e.what(), "test.lua:2: Mesh: has no faces (set its vertices and indices)");
  }
}

TEST_F(BindingErrorTest, SceneMethodsCheckTheirArguments) {
  EXPECT_EQ(runLua("Scene():add_entity(Light())"),
            "test.lua:1: Scene:add_entity: argument 1 expects an entity (Sphere, Cylinder, Cone, "
            "Cube, Mesh, Plane, Torus, Union, Merge, Intersection or Difference), got Light");
  EXPECT_EQ(runLua("Scene():add_entities({Sphere(), 3})"),
            "test.lua:1: Scene:add_entities: argument 1, entry 2 expects an entity (Sphere, "
            "Cylinder, Cone, Cube, Mesh, Plane, Torus, Union, Merge, Intersection or Difference), "
            "got number");
  EXPECT_EQ(
      runLua("Scene():add_light(Sphere())"),
      "test.lua:1: Scene:add_light: argument 1 expects a light (Light or SpotLight), got Sphere");
  EXPECT_EQ(runLua("Scene():add_lights(Light())"),
            "test.lua:1: Scene:add_lights: argument 1 expects a list, got Light");
  EXPECT_EQ(runLua("Scene().add_light(Light())"),
            "test.lua:1: Scene:add_light: self expects a Scene, got Light (call methods with ':')");
}

TEST_F(BindingErrorTest, ErrorsInsideFunctionsNameTheCallingLineAndCarryATraceback) {
  std::string full =
      runLuaFull("local function make()\n  return Finish() { diffuse = true }\nend\nmake()");
  EXPECT_EQ(full.rfind("test.lua:2: Finish: attribute 'diffuse' expects a number, got boolean", 0),
            0u)
      << full;
  EXPECT_NE(full.find("stack traceback:"), std::string::npos) << full;
  EXPECT_NE(full.find("test.lua:4:"), std::string::npos) << full;
  EXPECT_EQ(runLua("local a = nil\nlocal b = a.field"),
            "test.lua:2: attempt to index a nil value (local 'a')");
  EXPECT_EQ(runLua("local a = = 1"), "test.lua:1: unexpected symbol near '='");
}

TEST_F(BindingErrorTest, ForeignUserdataIsNotMistakenForAnObject) {
  EXPECT_EQ(runLua("local f = io.open('lua_fixture.h')\nLight().color = f"),
            "test.lua:2: Light: attribute 'color' expects a Color, got FILE*");
}

using SandboxTest = LuaFixture;

TEST_F(SandboxTest, OnlySafeLibrariesAreOpen) {
  EXPECT_TRUE(
      truth("os.execute == nil and os.remove == nil and os.rename == nil and os.exit == nil"));
  EXPECT_TRUE(truth("io.popen == nil and io.write == nil and io.output == nil"));
  EXPECT_TRUE(truth("require == nil and package == nil and debug == nil"));
  EXPECT_TRUE(truth("type(os.clock()) == 'number' and type(os.time()) == 'number' and "
                    "type(os.date()) == 'string'"));
  EXPECT_TRUE(truth("math.sqrt(4) == 2 and string.rep('a', 2) == 'aa' and utf8.char(65) == 'A' and "
                    "table.concat({1, 2}) == '12'"));
}

TEST_F(SandboxTest, FilesOpenOnlyForReadingRelativeToTheScript) {
  EXPECT_TRUE(truth("io.open('lua_fixture.h'):read('l'):find('Test fixture') ~= nil"));
  EXPECT_TRUE(truth("io.lines('lua_fixture.h')() ~= nil"));
  EXPECT_EQ(
      runLua("io.open('x.txt', 'w')"),
      "test.lua:1: io.open: only read mode is allowed in scene scripts (--unsafe lifts this)");
  EXPECT_EQ(
      runLua("io.open('x.txt', 'a+')"),
      "test.lua:1: io.open: only read mode is allowed in scene scripts (--unsafe lifts this)");
}

TEST_F(SandboxTest, LoadAcceptsTextButNotBinaryChunks) {
  EXPECT_EQ(num("load('return 1 + 2')()"), 3);
  EXPECT_TRUE(truth("select(2, load(string.dump(function() end))):find('binary') ~= nil"));
}

TEST_F(SandboxTest, DofileAndLoadfileReadTextRelativeToTheScript) {
  // lua_fixture.h is not Lua: loading it fails with a syntax error naming it.
  EXPECT_TRUE(truth("select(2, loadfile('lua_fixture.h')):find('lua_fixture.h:1:') ~= nil"));
  EXPECT_TRUE(truth("select(2, loadfile('no_such.lua')):find('no_such.lua') ~= nil"));
  std::string error = runLua("dofile('no_such.lua')");
  EXPECT_EQ(error.rfind("test.lua:1: ", 0), 0u) << error;
  EXPECT_NE(error.find("no_such.lua: No such file"), std::string::npos) << error;
}

TEST_F(SandboxTest, UnsafeLiftsTheSandbox) {
  ScriptOptions options;
  options.unsafe = true;
  reset(LRAY_SOURCE_DIR "/tests/bindings", options);
  EXPECT_TRUE(truth("os.execute ~= nil and io.popen ~= nil and require ~= nil"));
}

TEST_F(SandboxTest, RunawayScriptsTimeOut) {
  ScriptOptions options;
  options.timeoutSeconds = 0.2;
  reset(LRAY_SOURCE_DIR "/tests/bindings", options);
  auto start = std::chrono::steady_clock::now();
  std::string error = runLua("local i = 0\nwhile true do i = i + 1 end");
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(error.rfind("test.lua:2: the script ran longer than 0.2", 0), 0u) << error;
  EXPECT_NE(error.find("--script-timeout"), std::string::npos) << error;
  EXPECT_LT(seconds, 5);
  // The next call gets a fresh budget.
  EXPECT_EQ(runLua("local a = 1"), "");
}

} // namespace
} // namespace lray::lua
