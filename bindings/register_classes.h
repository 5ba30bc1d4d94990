// Pipeline: script -> scene description. Registration of every LRay class
// and function (lua/README.md) into a lua_State, one file per family.
#pragma once

#include "bindings/lua_binding.h"

namespace lray::lua {

void registerValueClasses(Registry &reg);   ///< Vector, Color, Transform and its factories
void registerTextureClasses(Registry &reg); ///< Texture, Finish, pigments, texture maps
void registerEntityClasses(Registry &reg);  ///< the shapes, Mesh, mesh_from_obj
void registerCsgClasses(Registry &reg);     ///< Union, Merge, Intersection, Difference
void registerSceneClasses(Registry &reg);   ///< SceneInfo, Scene, Perspective, the lights

/// The attributes every entity class has (shapes, Mesh, CSG nodes):
/// texture first, so that its object lives in user value slot 1
/// (CsgObj::kChildrenSlot and Mesh:copy count on it), then transform.
template <class T> ClassBuilder<T> &entityAttributes(ClassBuilder<T> &b) {
  return b.attr("texture", &T::texture).attr("transform", &T::transform);
}

/// All of the above, in dependency order; the state's BindingContext must be attached.
void registerAllClasses(lua_State *L);

} // namespace lray::lua
