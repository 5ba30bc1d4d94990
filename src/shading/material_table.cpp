// Pipeline: shading. See material_table.h.
#include "shading/material_table.h"

namespace lray {

MaterialTable::MaterialTable(const Scene &scene, bool anyLight) {
  materials_.reserve(scene.textures.size() + 1);
  for (const Texture &texture : scene.textures)
    materials_.push_back(Material::prepare(texture.finish, texture.pigment, anyLight));
  // Fallback for an out-of-range texture index: default Finish, pigment 0
  // (or black when the table is empty, as evaluatePigment returns for it).
  materials_.push_back(Material::prepare(Finish{}, 0, anyLight));
  entityMaterial_.reserve(scene.entities.size());
  for (const Entity &entity : scene.entities) {
    entityMaterial_.push_back(entity.texture < scene.textures.size()
                                  ? entity.texture
                                  : static_cast<uint32_t>(scene.textures.size()));
  }
}

} // namespace lray
