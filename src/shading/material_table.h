// Pipeline: shading. The frame's materials: one prepared Material (phong.h)
// per Scene::textures entry plus a default, and which one each entity uses.
#pragma once

#include "scene/scene.h"
#include "shading/phong.h"

#include <cstdint>
#include <vector>

namespace lray {

class MaterialTable {
public:
  /// `anyLight`: the frame has a light that emits (else nothing is lit).
  MaterialTable(const Scene &scene, bool anyLight);

  /// The material of entity `entity` (the default for an index out of range).
  const Material &ofEntity(uint32_t entity) const {
    return materials_[entity < entityMaterial_.size() ? entityMaterial_[entity]
                                                      : materials_.size() - 1];
  }

private:
  std::vector<Material> materials_;      ///< per Scene::textures entry, plus a default last
  std::vector<uint32_t> entityMaterial_; ///< per Scene::entities entry
};

} // namespace lray
