// Robustness suite (issue 8): NaN and Inf written in a scene script (Lua
// `0/0`, `1/0`) are rejected with a SceneError when the script loads or
// its frame is built, never dropped silently and never carried into the
// render; and scenes with extreme but finite finishes render no NaN/Inf.
#include "run/frame_pipeline.h"
#include "bindings/scene_script.h"
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <string>

namespace lray::stress {
namespace {

/// Loads `body` (statements run inside scene(clock) with `s` a Scene) and
/// builds frame 0; returns the SceneError's message, or "" if none.
std::string loadError(const std::string &prelude, const std::string &body) {
  std::string source = prelude + "\nfunction scene(clock)\n  local s = Scene()\n" + body +
                       "\n  return s\nend\n";
  try {
    SceneScript script = SceneScript::fromString(source, "nonfinite.lua");
    Scene scene = script.buildFrame(0);
  } catch (const SceneError &e) {
    return e.what();
  }
  return "";
}

struct BadInput {
  const char *name;
  const char *prelude; ///< top level (runs at load)
  const char *body;    ///< inside scene(clock)
};

const BadInput kBadInputs[] = {
    {"NaN vector in Translate", "", "s:add_entity(Sphere(Translate(Vector(0/0, 0, 0))))"},
    {"Inf vector in Translate", "", "s:add_entity(Sphere(Translate(Vector(1, 1/0, 0))))"},
    {"NaN Translate at top level", "local t = Translate(Vector(0, 0, 0/0))", ""},
    {"NaN Scale", "", "s:add_entity(Cube(Scale(0/0, 1, 1)))"},
    {"Inf uniform Scale", "", "s:add_entity(Cube(Scale(1/0)))"},
    {"NaN Rotate angle", "", "s:add_entity(Cube(Rotate(y, 0/0)))"},
    {"Inf Rotate angle", "", "s:add_entity(Cube(Rotate(y, 1/0)))"},
    {"NaN Rotate axis", "", "s:add_entity(Cube(Rotate(Vector(0/0, 1, 0), 30)))"},
    {"NaN LookAt position", "",
     "s.camera = Perspective() { transform = LookAt(Vector(0/0, 0, 0), Vector(0, 0, 1), y) }"},
    {"Inf transform by assignment", "",
     "local c = Cylinder(); c.transform = Translate(Vector(-1/0, 0, 0)); s:add_entity(c)"},
    {"NaN light transform", "",
     "s:add_light(Light() { transform = Translate(Vector(0, 0/0, 0)) })"},
    {"NaN mesh vertex", "",
     "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0/0, 0}, {0, 1, 0}}, indices = {{1, 2, 3}} "
     "})"},
    {"Inf mesh vertex", "",
     "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, -1/0}}, indices = {{1, 2, 3}} "
     "})"},
    {"NaN mesh normal", "",
     "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, normals = {{0, 0/0, 1}}, "
     "indices = {{{1, nil, 1}, {2, nil, 1}, {3, nil, 1}}} })"},
    {"Inf mesh uv", "",
     "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, uvs = {{0, 1/0}}, "
     "indices = {{{1, 1}, {2, 1}, {3, 1}}} })"},
    {"NaN colour", "", "s.background_color = Color(0/0, 0, 0)"},
    {"NaN light colour", "", "s:add_light(Light() { color = Color(1, 1/0, 1) })"},
    {"NaN diffuse", "",
     "s:add_entity(Sphere() { texture = Texture() { finish = Finish() { diffuse = 0/0 } } })"},
    {"Inf reflection", "",
     "s:add_entity(Sphere() { texture = Texture() { finish = Finish() { reflection = 1/0 } } })"},
    {"NaN field of view", "", "s.camera = Perspective(0/0, 1)"},
    {"NaN image width", "scene_info = SceneInfo() { image_width = 0/0 }", ""},
    {"NaN clock", "scene_info = SceneInfo() { start_clock = 0/0 }", ""},
    {"NaN marble frequency", "",
     "s:add_entity(Sphere() { texture = Texture() { pigment = MarblePigment3D() { frequency = "
     "Vector(0/0, 1, 1) } } })"},
};

TEST(StressNonFiniteInput, EveryNonFiniteValueIsASceneError) {
  for (const BadInput &c : kBadInputs) {
    std::string message = loadError(c.prelude, c.body);
    EXPECT_NE(message, "") << c.name << ": accepted";
    // The message says where (the script) and what.
    if (!message.empty()) {
      EXPECT_NE(message.find("nonfinite.lua"), std::string::npos) << c.name << ": " << message;
    }
  }
}

TEST(StressNonFiniteInput, MessagesNameTheProblem) {
  // The values that reach geometry name the non-finite number.
  for (const BadInput &c : kBadInputs) {
    std::string message = loadError(c.prelude, c.body);
    if (message.empty()) continue; // reported by the test above
    bool named =
        message.find("finite") != std::string::npos || message.find("nan") != std::string::npos ||
        message.find("NaN") != std::string::npos || message.find("inf") != std::string::npos ||
        message.find("singular") != std::string::npos;
    EXPECT_TRUE(named) << c.name << ": " << message;
  }
}

// A mesh coordinate finite as a Lua number but beyond single precision
// (mesh positions are float) must not silently become Inf.
TEST(StressNonFiniteInput, MeshValueBeyondSinglePrecision) {
  EXPECT_NE(loadError("", "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1e39, 0, 0}, {0, 1, 0}}, "
                          "indices = {{1, 2, 3}} })"),
            "");
  EXPECT_NE(
      loadError(
          "", "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, "
              "normals = {{0, 0, -1e39}}, indices = {{{1, nil, 1}, {2, nil, 1}, {3, nil, 1}}} })"),
      "");
}

TEST(StressNonFiniteInput, ValidSceneStillLoads) {
  // Control for the cases above: the same shapes with finite values load.
  EXPECT_EQ(
      loadError("", "s:add_entity(Sphere(Translate(Vector(1, 2, 3)) * Scale(2) * Rotate(y, 30)))\n"
                    "s:add_entity(Mesh() { vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, "
                    "indices = {{1, 2, 3}} })\n"
                    "s:add_light(Light() { color = Color(1, 1, 1) })"),
      "");
}

TEST(StressNonFinitePixels, ExtremeFinishesRenderNoNaN) {
  // Finite but extreme finishes and geometry: exponent 0 and huge, index
  // of refraction tiny and huge, negative absorption, full reflection and
  // refraction at once, a light inside an object, a camera inside a sphere.
  const std::string source = R"lua(
scene_info = SceneInfo() { image_width = 48, image_height = 36 }
local function finish(t) return Texture() { finish = Finish() (t) } end
function scene(clock)
  local s = Scene() { camera = Perspective(60, 48 / 36) { transform = LookAt(Vector(0, 2, -6), Vector(0, 0.5, 0), y) } }
  s:add_entity(Floor() { texture = finish { reflection = 1, refraction = 1, refraction_index = 1e-6 } })
  s:add_entity(Sphere(Translate(Vector(-1.5, 1, 0))) { texture = finish { exponent = 0, specular = 1 } })
  s:add_entity(Sphere(Translate(Vector(1.5, 1, 0)) * Scale(1, 1e-6, 1)) { texture = finish { exponent = 1e6, specular = 1 } })
  s:add_entity(Cube(Translate(Vector(0, 0.5, 2))) { texture = finish { refraction = 1, refraction_index = 1e6, absorption = -1 } })
  s:add_entity(Cylinder(Translate(Vector(0, 0, -1)) * Scale(0.3, 2, 0.3)) { texture = finish { refraction = 0.9, refraction_index = 1.5, reflection = 0.5 } })
  s:add_entity(Cone(Translate(Vector(2.5, 0, -1))) { open = true, texture = finish { refraction = 1, refraction_index = 0.5 } })
  s:add_entity(Sphere(Translate(Vector(0, 2, -6)) * Scale(0.5)) { texture = finish { refraction = 1 } })
  s:add_light(Light() { transform = Translate(Vector(-1.5, 1, 0)) })
  s:add_light(Light() { rows = 3, cols = 3, area = true, transform = Translate(Vector(3, 6, -4)) * Scale(1e-9) })
  return s
end
)lua";
  for (BackendKind kind : kBothBackends) {
    SceneScript script = SceneScript::fromString(source, "extreme.lua");
    Scene scene = script.buildFrame(0);
    renderChecked(scene, kind, 48, 36, 2);
  }
}

TEST(StressNonFinitePixels, DegenerateMeshThroughTheWholePipeline) {
  // A script mesh with zero-area faces (repeated corner, equal positions,
  // collinear corners), a sliver, a polygon fanned over a repeated vertex,
  // smooth normals computed from all of them, and copies under a tiny and
  // a huge scale; rendered end to end by renderScriptFrame.
  const std::string source = R"lua(
scene_info = SceneInfo() { image_width = 40, image_height = 30, samples = 2 }
function scene(clock)
  local s = Scene() { camera = Perspective(50, 40 / 30) { transform = LookAt(Vector(1, 1, -5), Vector(1, 1, 0), y) } }
  local m = Mesh() {
    smooth = true,
    vertices = { {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, 0}, {1, 1, 0}, {3, 3, 0}, {1, 1, 1e-7}, {2, 2, 0} },
    indices = { {1, 2, 3}, {4, 4, 4}, {4, 5, 4}, {1, 4, 6}, {4, 7, 8}, {1, 2, 2, 3, 3}, {2, 5, 8, 4} },
  }
  s:add_entity(m)
  s:add_entity(m:copy() { transform = Translate(Vector(2.5, 0, 0)) * Scale(1e-4) })
  s:add_entity(m:copy() { transform = Translate(Vector(-1e4, -1e4, 1e5)) * Scale(1e4) })
  s:add_light(Light() { transform = Translate(Vector(0, 3, -4)) })
  return s
end
)lua";
  for (BackendKind kind : kBothBackends) {
    SceneScript script = SceneScript::fromString(source, "degenerate.lua");
    ImageCache images(false);
    FrameStats stats;
    Film film = renderScriptFrame(script, script.info(), 0, backendName(kind), images, stats);
    EXPECT_EQ(stats.rays.nonFinite, 0u) << backendName(kind);
    EXPECT_EQ(stats.rays.camera, 40u * 30u * 4u);
    EXPECT_GT(stats.rays.shadow + stats.rays.shadowSkipped, 0u) << "the mesh should be hit and lit";
  }
}

} // namespace
} // namespace lray::stress
