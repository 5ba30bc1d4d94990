// Pipeline: shading. See material_table.h.
#include "shading/material_table.h"

#include "geometry/csg_tree.h"

namespace lray {

MaterialTable::MaterialTable(const Scene &scene, bool anyLight) {
  materials_.reserve(scene.textures.size() + 1);
  for (const Texture &texture : scene.textures)
    materials_.push_back(Material::prepare(texture.finish, texture.pigment, anyLight));
  // Fallback for an out-of-range texture index: default Finish, pigment 0
  // (or black when the table is empty, as evaluatePigment returns for it).
  materials_.push_back(Material::prepare(Finish{}, 0, anyLight));
  const auto material = [&](uint32_t texture) {
    return texture < scene.textures.size() ? texture : static_cast<uint32_t>(scene.textures.size());
  };
  entities_.reserve(scene.entities.size());
  for (const Entity &entity : scene.entities) {
    const Csg *csg = std::get_if<Csg>(&entity.shape);
    if (!csg || !csg->tree) {
      entities_.push_back({material(entity.texture), false});
      continue;
    }
    entities_.push_back({static_cast<uint32_t>(leafMaterial_.size()), true});
    for (const CsgTree::Leaf &leaf : csg->tree->leaves)
      leafMaterial_.push_back(material(leaf.entity.texture));
  }
}

} // namespace lray
