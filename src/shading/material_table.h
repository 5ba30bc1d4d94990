// Pipeline: shading. The frame's materials: one prepared Material (phong.h)
// per Scene::textures entry plus a default, and which one each hit uses: its
// entity's, or for a CSG entity its leaf's (Hit::primitive).
#pragma once

#include "math/hit.h"
#include "scene/scene.h"
#include "shading/phong.h"

#include <cstdint>
#include <vector>

namespace lray {

class MaterialTable {
public:
  /// `anyLight`: the frame has a light that emits (else nothing is lit).
  MaterialTable(const Scene &scene, bool anyLight);

  /// The material of what `hit` struck (the default for an entity index out
  /// of range).
  const Material &ofHit(const Hit &hit) const {
    if (hit.entity >= entities_.size()) return materials_.back();
    const EntityMaterials &e = entities_[hit.entity];
    return materials_[e.perLeaf ? leafMaterial_[e.first + hit.primitive] : e.first];
  }

private:
  struct EntityMaterials {
    uint32_t first;       ///< the material, or per leaf: its first entry in leafMaterial_
    bool perLeaf = false; ///< a CSG entity: one material per leaf
  };
  std::vector<Material> materials_;    ///< per Scene::textures entry, plus a default last
  std::vector<EntityMaterials> entities_; ///< per Scene::entities entry
  std::vector<uint32_t> leafMaterial_; ///< CSG leaves' materials, entity after entity
};

} // namespace lray
