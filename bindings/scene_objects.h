// Pipeline: script -> scene description. The C++ objects that live inside
// Lua userdata while a scene script runs. They are reference types, as in
// the original LRay: a Texture assigned to two entities is one object, and
// changing it later is seen by both. Pointers between them are kept alive
// by Lua user values (see lua_binding.h); the converter (scene_converter.h)
// turns them into the plain model of src/scene/scene.h.
#pragma once

#include "bindings/external_memory.h"

#include "bindings/lua_binding.h"
#include "scene/mesh_builder.h"
#include "scene/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace lray::lua {

struct SceneInfoObj : SceneInfo {
  static constexpr const char *kLuaName = "a SceneInfo";
  ScriptLoc loc;
};

struct FinishObj : Finish {
  static constexpr const char *kLuaName = "a Finish";
};

/// TextureMap2D, UVMap, SphericalMap, CylindricalMap.
struct Map2DObj : TextureMap {
  static constexpr const char *kLuaName =
      "a 2-D texture map (TextureMap2D, UVMap, SphericalMap or CylindricalMap)";
  ScriptLoc loc;
};

/// TextureMap3D, LinearMap.
struct Map3DObj : TextureMap {
  static constexpr const char *kLuaName = "a 3-D texture map (TextureMap3D or LinearMap)";
  ScriptLoc loc;
};

/// Every pigment class (shading/pigments/); `pattern` says which, with its
/// parameters. The references to other objects live here, outside the model.
struct PigmentObj {
  static constexpr const char *kLuaName =
      "a pigment (ColorPigment, CheckerPigment2D, CheckerPigment3D, MarblePigment3D, "
      "WoodPigment3D or ImagePigment2D)";
  PigmentPattern pattern;
  PigmentObj *pigment1 = nullptr; ///< checkers; null = default white
  PigmentObj *pigment2 = nullptr;
  Map2DObj *map2 = nullptr; ///< 2-D pigments; null = TextureMap2D()
  Map3DObj *map3 = nullptr; ///< 3-D pigments; null = TextureMap3D()
  std::string imagePath;    ///< ImagePigment2D: absolute path
  ScriptLoc loc;
};

struct TextureObj {
  static constexpr const char *kLuaName = "a Texture";
  ScriptLoc loc;
  FinishObj *finish = nullptr;   ///< null = Finish()
  PigmentObj *pigment = nullptr; ///< null = white ColorPigment
};

/// Every analytic shape class (geometry/shapes/); `shape` says which, with
/// its parameters. Kept small (one per object in big scenes).
struct EntityObj {
  static constexpr const char *kLuaName = "an entity (a shape or a Mesh)";
  Affine transform;                ///< worldFromObject
  TextureObj *texture = nullptr;   ///< null = Texture()
  ScriptLoc loc;
  Shape shape;
};

/// Geometry shared by a mesh and its copies; the built MeshData is cached
/// here so copies share one set of arrays.
struct MeshGeometry {
  MeshSource source;
  mutable MeshDataPtr built; ///< null until first needed; reset when the source changes
  lua::MemoryCharge charge;  ///< the source's arrays, against --script-memory
};

struct MeshObj {
  static constexpr const char *kLuaName = "a Mesh";
  std::shared_ptr<MeshGeometry> geometry = std::make_shared<MeshGeometry>();
  Affine transform;
  TextureObj *texture = nullptr;
  ScriptLoc loc;
  bool smooth = false;

  /// The geometry for writing: unshared first (copy on write), cache dropped.
  MeshSource &editSource() {
    if (geometry.use_count() > 1) geometry = std::make_shared<MeshGeometry>(*geometry);
    geometry->built.reset();
    return geometry->source;
  }
};

struct CameraObj : Camera {
  static constexpr const char *kLuaName = "a camera (Perspective, Orthographic or Spherical)";
  ScriptLoc loc;
};

/// Every light class (shading/lights/); `light` says which, with its
/// parameters.
struct LightObj {
  static constexpr const char *kLuaName = "a light";
  SceneLight light;
  ScriptLoc loc;
};

/// What an EntityRef points to.
enum class EntityRefKind : uint8_t { Shape, Mesh, Csg };

/// One entry of Scene:add_entity (or of a CSG node's children), in order.
struct EntityRef {
  const void *object; ///< EntityObj, MeshObj or CsgObj, by `kind`
  EntityRefKind kind;
};

/// Union, Merge, Intersection and Difference (geometry/shapes/csg.h). The
/// children are kept alive by a Lua table in user value kChildrenSlot.
struct CsgObj {
  static constexpr const char *kLuaName = "a CSG node (Union, Merge, Intersection or Difference)";
  static constexpr int kChildrenSlot = 2; ///< after the texture's (slot 1)
  Affine transform;              ///< on top of the children's own
  TextureObj *texture = nullptr; ///< null: none; children without one inherit it
  ScriptLoc loc;
  CsgOp op = CsgOp::Union;
  std::vector<EntityRef> children; ///< shapes and CSG nodes
};

/// The end of the message for a shape that an attribute left without an
/// inside (hollowedBy in geometry/shapes/shape_list.h), such as "open".
inline std::string noInside(const char *attribute) {
  return std::string("has no inside (CSG needs solids: set ") + attribute + " = false)";
}

struct SceneObj {
  static constexpr const char *kLuaName = "a Scene";
  Color background{0, 0, 0};
  CameraObj *camera = nullptr; ///< null = Perspective()
  std::vector<EntityRef> entities;
  std::vector<const LightObj *> lights;
};

} // namespace lray::lua
