// Fuzz target (libFuzzer): the Lua binding surface (bindings/). The input
// bytes are read as a tiny program that writes a Lua scene script: random
// constructor calls, attribute assignments (dot and bulk), operators and
// method calls with arguments of random types (numbers including NaN, Inf,
// huge and denormal ones, strings, booleans, nil, tables, functions, other
// objects), each statement under pcall so one error does not end the
// script. The script then goes through SceneScript::fromString and
// buildFrame. A SceneError is fine; a crash, a sanitizer report, another
// exception or a scene holding a non-finite number is a bug.
#include "bindings/scene_script.h"
#include "geometry/csg_tree.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace {

const char *const kConstructors[] = {
    "Vector", "Color", "Translate", "Scale", "Rotate", "LookAt", "Identity", "Sphere", "Cube",
    "Cylinder", "Cone", "Mesh", "Light", "Texture", "Finish", "ColorPigment", "CheckerPigment2D",
    "CheckerPigment3D", "MarblePigment3D", "WoodPigment3D", "ImagePigment2D", "TextureMap2D",
    "UVMap", "SphericalMap", "CylindricalMap", "TextureMap3D", "LinearMap", "Perspective", "Scene",
    "SceneInfo", "Floor", "grey", "mesh_from_obj", "tostring", "type", "getmetatable", "Union",
    "Merge", "Intersection", "Difference"};

/// The scene's folder, made once per process: the sandbox refuses a
/// folder that does not exist (every input then stopped before its first
/// statement), and mesh_from_obj and ImagePigment2D get real files to read.
char gBaseDir[] = "/tmp/lray-binding-fuzz-XXXXXX";

void removeBaseDir() {
  std::error_code ec;
  std::filesystem::remove_all(gBaseDir, ec);
}

const char *baseDir() {
  static const bool made = [] {
    if (!mkdtemp(gBaseDir)) std::abort();
    std::atexit(&removeBaseDir);
    const std::string dir = gBaseDir;
    std::ofstream(dir + "/mesh.obj")
        << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    std::ofstream(dir + "/texture.ppm", std::ios::binary)
        << "P6\n2 2\n255\n"
        << std::string("\xff\x00\x00\x00\xff\x00\x00\x00\xff\xff\xff\xff", 12);
    return true;
  }();
  (void)made;
  return gBaseDir;
}

const char *const kCsgClasses[] = {"Union", "Merge", "Intersection", "Difference"};

const char *const kAttributes[] = {
    "x", "y", "z", "r", "g", "b", "color", "transform", "texture", "finish", "pigment", "rows",
    "cols", "area", "vertices", "normals", "uvs", "indices", "smooth", "open", "ambient", "diffuse",
    "specular", "exponent", "reflection", "refraction", "refraction_index", "absorption",
    "image_width", "image_height", "frames", "samples", "start_clock", "end_clock", "camera",
    "background_color", "fov", "aspect", "pigment1", "pigment2", "texture_map", "color1", "color2",
    "frequency", "period", "power", "size", "scale_s", "scale_t", "translate_s", "translate_t",
    "colour", "__index", "__gc", "add_entity", "children", "major", "minor"};

const char *const kMethods[] = {"dot", "cross", "length", "normalized", "inverse", "copy",
                                "add_entity", "add_entities", "add_light", "add_lights"};

const char *const kNumbers[] = {"0", "1", "-1", "0.5", "2", "3", "100", "1e308", "-1e308", "0/0",
                                "1/0", "-1/0", "2^53", "1e-320", "math.huge", "1e-9", "1e9",
                                "-0.0", "math.pi", "2^31", "-(2^31)", "7.5"};

const char *const kLiterals[] = {
    "nil", "true", "false", "'s'", "''", "'missing.obj'", "{}", "{1, 2, 3}", "{0/0, 1, 2}",
    "{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}", "{{1, 2, 3}}", "{{1, 2, 3}, {3, 2, 4}}",
    "{{{1, 1, 1}, {2, 2, 2}, {3, 3, 3}}}", "{{0, 0}, {1, 0}, {0, 1}}", "{{1, nil, 1}}",
    "{{0, 0, 1}}", "function() end", "x", "y", "z", "origin", "white", "black", "red",
    "{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}", "{{1, 2, 3, 4}}", "{{-1, 2, 3}}", "{{1, 2, 99}}",
    "{{1e30, 0, 0}, {0, 1e30, 0}, {0, 0, 1e30}}", "{{1.5, 2, 3}}", "'mesh.obj'",
    "'texture.ppm'"};

class Writer {
public:
  explicit Writer(FuzzedDataProvider &in) : in_(in) {}

  std::string variable() { return "v[" + std::to_string(in_.ConsumeIntegralInRange(1, 6)) + "]"; }

  std::string expr(int depth) {
    if (depth > 3 || in_.remaining_bytes() == 0) return leaf();
    switch (in_.ConsumeIntegralInRange(0, 10)) {
    case 0:
    case 1:
    case 2: { // constructor call with 0..4 arguments
      std::string s = pick(kConstructors);
      s += "(";
      int n = in_.ConsumeIntegralInRange(0, 4);
      for (int i = 0; i < n; ++i) s += (i ? ", " : "") + expr(depth + 1);
      return s + ")";
    }
    case 3: { // binary operator
      const char *ops[] = {" + ", " - ", " * ", " / ", " == ", " .. "};
      return "(" + expr(depth + 1) + pick(ops) + expr(depth + 1) + ")";
    }
    case 4: return "(-" + expr(depth + 1) + ")";
    case 5: { // method call
      std::string s = "(" + expr(depth + 1) + "):" + pick(kMethods) + "(";
      int n = in_.ConsumeIntegralInRange(0, 2);
      for (int i = 0; i < n; ++i) s += (i ? ", " : "") + expr(depth + 1);
      return s + ")";
    }
    case 6: return "(" + expr(depth + 1) + ")." + pick(kAttributes);
    case 7: { // bulk call: obj { attr = value, ... }
      std::string s = "(" + expr(depth + 1) + ") {";
      int n = in_.ConsumeIntegralInRange(0, 3);
      for (int i = 0; i < n; ++i)
        s += std::string(i ? ", " : " ") + pick(kAttributes) + " = " + expr(depth + 1);
      return s + " }";
    }
    case 8: return "{" + expr(depth + 1) + ", " + expr(depth + 1) + "}";
    case 9: { // CSG: Op { solid, ..., attr = value }
      std::string s = std::string(pick(kCsgClasses)) + " {";
      int n = in_.ConsumeIntegralInRange(0, 3);
      for (int i = 0; i < n; ++i) s += std::string(i ? ", " : " ") + expr(depth + 1);
      if (in_.ConsumeBool())
        s += std::string(n ? ", " : " ") + pick(kAttributes) + " = " + expr(depth + 1);
      return s + " }";
    }
    default: return leaf();
    }
  }

  std::string leaf() {
    switch (in_.ConsumeIntegralInRange(0, 3)) {
    case 0: return pick(kNumbers);
    case 1: return pick(kLiterals);
    case 2: return variable();
    default: return std::to_string(in_.ConsumeIntegralInRange(-3, 300));
    }
  }

  std::string statement() {
    switch (in_.ConsumeIntegralInRange(0, 7)) {
    case 0:
    case 1: return variable() + " = " + expr(0);
    case 2: return variable() + "." + pick(kAttributes) + " = " + expr(0);
    case 3: return "S:add_entity(" + expr(0) + ")";
    case 4: return "S:add_light(" + expr(0) + ")";
    case 5:
      return "S." + std::string(in_.ConsumeBool() ? "camera" : "background_color") + " = " +
             expr(0);
    case 6: return "scene_info = " + expr(0);
    default: return "S:add_entities({" + expr(0) + ", " + expr(0) + "})";
    }
  }

private:
  template <size_t N> const char *pick(const char *const (&list)[N]) {
    return list[in_.ConsumeIntegralInRange<size_t>(0, N - 1)];
  }
  FuzzedDataProvider &in_;
};

bool finite(const lray::Vec3 &v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(const lray::Color &c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}
bool finite(const lray::Transform &t) {
  for (const auto &row : t.matrix().m)
    for (double x : row)
      if (!std::isfinite(x)) return false;
  for (const auto &row : t.inverseMatrix().m)
    for (double x : row)
      if (!std::isfinite(x)) return false;
  return !t.singular();
}

void check(bool ok) {
  if (!ok) std::abort();
}

/// Nothing non-finite may reach the scene model (it would become NaN pixels).
void checkScene(const lray::Scene &s) {
  check(finite(s.background));
  check(finite(s.camera.worldFromCamera) && std::isfinite(s.camera.fov) &&
        std::isfinite(s.camera.aspect));
  for (const lray::Entity &e : s.entities) {
    check(finite(e.worldFromObject));
    if (const auto *csg = std::get_if<lray::Csg>(&e.shape)) {
      check(csg->tree != nullptr && !csg->tree->leaves.empty());
      for (const lray::CsgTree::Leaf &leaf : csg->tree->leaves) {
        check(finite(leaf.entity.worldFromObject) && leaf.entity.texture < s.textures.size());
        check(leaf.entity.kind() != lray::ShapeKind::Csg && !leaf.entity.isMesh());
      }
      for (const lray::CsgTree::Node &node : csg->tree->nodes) check(node.children > 0);
    }
    if (e.kind() == lray::ShapeKind::Mesh) {
      check(e.mesh != nullptr);
      for (const lray::Vec3f &p : e.mesh->positions)
        check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      for (uint32_t i : e.mesh->triangleIndices) check(i < e.mesh->positions.size());
    }
  }
  for (const lray::SceneLight &light : s.lights)
    std::visit([&](const auto &l) { check(finite(l.worldFromLight) && finite(l.color)); }, light);
  for (const lray::Texture &t : s.textures) {
    const lray::Finish &f = t.finish;
    check(finite(f.ambient) && std::isfinite(f.diffuse) && std::isfinite(f.specular) &&
          std::isfinite(f.exponent) && std::isfinite(f.reflection) && std::isfinite(f.refraction) &&
          std::isfinite(f.refractionIndex) && std::isfinite(f.absorption));
    check(t.pigment < s.pigments.size());
  }
  for (const lray::Pigment &p : s.pigments)
    std::visit(
        [&](const auto &k) {
          if constexpr (requires { k.color; }) check(finite(k.color));
          if constexpr (requires { k.frequency; }) check(finite(k.frequency));
        },
        p.pattern);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FuzzedDataProvider in(data, size);
  Writer w(in);
  std::string source = "v = {}\nS = Scene()\n";
  for (int i = 0; i < 24 && in.remaining_bytes() > 0; ++i)
    source += "pcall(function() " + w.statement() + " end)\n";
  source += "function scene(clock) return S end\n";
  lray::ScriptOptions options;
  options.timeoutSeconds = 2;
  // The default cap: the frame is built, never rendered, so a size within
  // it costs nothing. (A cap of 4096 pixels made the default 800x600
  // SceneInfo fail every input before buildFrame.)
  try {
    lray::SceneScript script =
        lray::SceneScript::fromString(source, "fuzz.lua", baseDir(), options);
    lray::Scene scene = script.buildFrame(script.info().startClock);
    checkScene(scene);
  } catch (const lray::SceneError &) {
    // A clear user error: fine.
  }
  return 0;
}
