// Pipeline: script -> scene description. SceneInfo, Scene, Perspective and
// Light (lua/README.md, "Scene and camera", "Lights").
#include "bindings/class_names.h"
#include "bindings/register_classes.h"
#include "bindings/scene_objects.h"
#include "bindings/validators.h"

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace lray::lua {

namespace {

// User value slot of the Scene's keep-alive list of entities and lights
// (after slot 1, the camera).
constexpr int kKeepAliveSlot = 2;

// Keeps `value` alive as long as the scene: appended to a list of chunks of
// kChunk entries. Only the newest chunk changes, so the generational
// collector does not re-traverse a million-entry table at every minor cycle.
constexpr lua_Integer kChunk = 4096;

void keepAlive(lua_State *L, int scene, int value) {
  if (lua_getiuservalue(L, scene, kKeepAliveSlot) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setiuservalue(L, scene, kKeepAliveSlot);
  }
  int chunks = lua_gettop(L);
  auto n = static_cast<lua_Integer>(lua_rawlen(L, chunks));
  if (n == 0 || lua_rawgeti(L, chunks, n) != LUA_TTABLE ||
      static_cast<lua_Integer>(lua_rawlen(L, -1)) >= kChunk) {
    lua_settop(L, chunks);
    lua_createtable(L, static_cast<int>(kChunk), 0);
    lua_pushvalue(L, -1);
    lua_rawseti(L, chunks, n + 1);
  }
  lua_pushvalue(L, value);
  lua_rawseti(L, -2, static_cast<lua_Integer>(lua_rawlen(L, -2) + 1));
  lua_settop(L, chunks - 1);
}

void addEntity(lua_State *L, SceneObj &scene, int value, const char *method, int argument,
               lua_Integer listIndex) {
  if (const EntityObj *e = toObject<EntityObj>(L, value)) {
    scene.entities.push_back({e, EntityRefKind::Shape});
  } else if (const MeshObj *m = toObject<MeshObj>(L, value)) {
    scene.entities.push_back({m, EntityRefKind::Mesh});
  } else if (const CsgObj *c = toObject<CsgObj>(L, value)) {
    scene.entities.push_back({c, EntityRefKind::Csg});
  } else {
    std::string where = listIndex > 0 ? ", entry " + std::to_string(listIndex) : std::string();
    throw ScriptError(std::string("Scene:") + method + ": argument " + std::to_string(argument) +
                      where + " expects an entity (" + classNames<Shape>() + "), got " +
                      typeName(L, value));
  }
  keepAlive(L, 1, value);
}

void addLight(lua_State *L, SceneObj &scene, int value, const char *method, int argument,
              lua_Integer listIndex) {
  const LightObj *light = toObject<LightObj>(L, value);
  if (!light) {
    std::string where = listIndex > 0 ? ", entry " + std::to_string(listIndex) : std::string();
    throw ScriptError(std::string("Scene:") + method + ": argument " + std::to_string(argument) +
                      where + " expects a light (" + classNames<SceneLight>() + "), got " +
                      typeName(L, value));
  }
  scene.lights.push_back(light);
  keepAlive(L, 1, value);
}

template <void (*Add)(lua_State *, SceneObj &, int, const char *, int, lua_Integer)>
int addOne(lua_State *L, const char *method) {
  SceneObj &scene = checkSelf<SceneObj>(L, (std::string("Scene:") + method).c_str());
  if (lua_gettop(L) != 2)
    throwArgumentCount((std::string("Scene:") + method).c_str(), 1, lua_gettop(L) - 1);
  Add(L, scene, 2, method, 1, 0);
  return 0;
}

template <void (*Add)(lua_State *, SceneObj &, int, const char *, int, lua_Integer)>
int addList(lua_State *L, const char *method) {
  SceneObj &scene = checkSelf<SceneObj>(L, (std::string("Scene:") + method).c_str());
  if (lua_type(L, 2) != LUA_TTABLE)
    throw ScriptError(std::string("Scene:") + method + ": argument 1 expects a list, got " +
                      typeName(L, 2));
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, 2));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, 2, i);
    Add(L, scene, lua_gettop(L), method, 1, i);
    lua_pop(L, 1);
  }
  return 0;
}

template <class K> void lightDefaults(LightObj &l) { l.light = K{}; }

/// Constructor argument `index` of class `cls`, when given: checked by
/// `valid` (validators.h), as an attribute's value is, and stored in `into`.
void numberArgument(const char *cls, int index, std::optional<double> value,
                    const char *(*valid)(const double &), double &into) {
  if (!value) return;
  if (const char *expected = valid(*value))
    throw ScriptError(std::string(cls) + ": argument " + std::to_string(index) + " expects " +
                      expected + ", got " + formatNumber(*value));
  into = *value;
}

/// The parameters of a light of class K (for partAttr).
template <class K> K &params(LightObj &l) { return std::get<K>(l.light); }

int addEntityMethod(lua_State *L) { return addOne<&addEntity>(L, "add_entity"); }
int addEntitiesMethod(lua_State *L) { return addList<&addEntity>(L, "add_entities"); }
int addLightMethod(lua_State *L) { return addOne<&addLight>(L, "add_light"); }
int addLightsMethod(lua_State *L) { return addList<&addLight>(L, "add_lights"); }

} // namespace

void registerSceneClasses(Registry &reg) {
  reg.cls<SceneInfoObj>("SceneInfo")
      .ctor(+[](SceneInfoObj &) {})
      .attr("image_width", &SceneInfo::imageWidth, positiveInteger)
      .attr("image_height", &SceneInfo::imageHeight, positiveInteger)
      .attr("frames", &SceneInfo::frames, positiveInteger)
      .attr("samples", &SceneInfo::samples, positiveInteger)
      .attr("noise_threshold", &SceneInfo::noiseThreshold, nonNegativeNumber)
      .attr("integrator", &SceneInfo::integrator, integratorName)
      .attr("max_depth", &SceneInfo::maxDepth, positiveInteger)
      .attr("start_clock", &SceneInfo::startClock)
      .attr("end_clock", &SceneInfo::endClock)
      .attr("shutter", &SceneInfo::shutter, unitInterval)
      .attr("motion_steps", &SceneInfo::motionSteps, motionStepCount);

  reg.cls<CameraObj>("Perspective")
      .ctor(+[](CameraObj &c, std::optional<double> fov, std::optional<double> aspect) {
        numberArgument("Perspective", 1, fov, fieldOfView, c.fov);
        numberArgument("Perspective", 2, aspect, positiveNumber, c.aspect);
      })
      .attr("transform", &Camera::worldFromCamera)
      .attr("fov", &Camera::fov, fieldOfView)
      .attr("aspect", &Camera::aspect, positiveNumber)
      .attr("aperture", &Camera::aperture, nonNegativeNumber)
      .attr("focal_distance", &Camera::focalDistance, positiveNumber);

  reg.cls<CameraObj>("Orthographic")
      .defaults(+[](CameraObj &c) { c.kind = CameraKind::Orthographic; })
      .ctor(+[](CameraObj &c, std::optional<double> width, std::optional<double> aspect) {
        numberArgument("Orthographic", 1, width, positiveNumber, c.width);
        numberArgument("Orthographic", 2, aspect, positiveNumber, c.aspect);
      })
      .attr("transform", &Camera::worldFromCamera)
      .attr("width", &Camera::width, positiveNumber)
      .attr("aspect", &Camera::aspect, positiveNumber);

  // Every direction, on an image that should be 2:1 (lray warns otherwise,
  // as for any camera whose aspect is not the image's).
  reg.cls<CameraObj>("Spherical")
      .defaults(+[](CameraObj &c) {
        c.kind = CameraKind::Spherical;
        c.aspect = 2;
      })
      .ctor(+[](CameraObj &) {})
      .attr("transform", &Camera::worldFromCamera);

  reg.cls<LightObj>("Light")
      .defaults(&lightDefaults<Light>)
      .ctor(+[](LightObj &) {})
      .partAttr<&params<Light>>("color", &Light::color)
      .partAttr<&params<Light>>("rows", &Light::rows, positiveInteger)
      .partAttr<&params<Light>>("cols", &Light::cols, positiveInteger)
      .partAttr<&params<Light>>("area", &Light::area)
      .partAttr<&params<Light>>("transform", &Light::worldFromLight);
  reg.cls<LightObj>("SpotLight")
      .defaults(&lightDefaults<SpotLight>)
      .ctor(+[](LightObj &) {})
      .partAttr<&params<SpotLight>>("color", &SpotLight::color)
      .partAttr<&params<SpotLight>>("transform", &SpotLight::worldFromLight)
      .partAttr<&params<SpotLight>>("angle", &SpotLight::angle, rightAngleOrLess)
      .partAttr<&params<SpotLight>>("falloff", &SpotLight::falloff, rightAngleOrLess);

  auto scene = reg.cls<SceneObj>("Scene");
  scene.ctor(+[](SceneObj &) {})
      .attr("background_color", &SceneObj::background)
      .attr("camera", &SceneObj::camera)
      .rawMethod("add_entity", &addEntityMethod)
      .rawMethod("add_entities", &addEntitiesMethod)
      .rawMethod("add_light", &addLightMethod)
      .rawMethod("add_lights", &addLightsMethod);
  [[maybe_unused]] int slot = scene.userValueSlot();
  assert(slot == kKeepAliveSlot);
}

void registerAllClasses(lua_State *L) {
  Registry reg(L);
  registerValueClasses(reg);
  registerTextureClasses(reg);
  registerEntityClasses(reg);
  registerCsgClasses(reg);
  registerSceneClasses(reg);
}

} // namespace lray::lua
