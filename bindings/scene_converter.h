// Pipeline: script -> scene description. The separate, tested step that
// turns the Lua-side objects of one frame into the plain model
// (src/scene/scene.h); after it the renderer never touches Lua.
#pragma once

#include "bindings/scene_objects.h"

namespace lray::lua {

/// Converts `scene` into the plain model:
/// - textures and pigments are deduplicated by object identity (a Texture
///   shared by many entities appears once); the pigment table is built
///   bottom-up, so a checker's sub-pigments have smaller indices;
/// - unassigned references get their documented defaults (Texture(), Finish(),
///   white ColorPigment, TextureMap2D/3D, Perspective());
/// - image paths are already absolute (resolved at construction) and are
///   deduplicated into Scene::images;
/// - every object (entity, light, camera, texture, pigment, texture map)
///   carries the script file:line where it was constructed;
/// - mesh geometry is built once per shared geometry and cached.
/// Throws SceneError (with the offending object's location) for a mesh
/// index out of range, an empty mesh, a singular transform, a pigment
/// that contains itself or a light whose values conflict (Light::invalid).
/// The model is charged against `memoryLimit` bytes (--render-memory; 0:
/// none) as it is made, each part at its line, and the charge is kept in
/// Scene::memory for the textures and the acceleration structure.
Scene convertScene(const SceneObj &scene, const BindingContext &ctx, uint64_t memoryLimit = 0);

} // namespace lray::lua
