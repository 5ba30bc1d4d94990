// Pipeline: shading. See image_pigment_2d.h.
#include "shading/pigments/image_pigment_2d.h"

#include "shading/pigments/texture_map.h"

namespace lray {

Color ImagePigment2D::evaluate(const PigmentContext &c) const {
  if (image >= c.table.imageCount || !c.table.images[image]) return {};
  TexCoord2 st = mapPoint2D(c.map, c.hit);
  return c.table.images[image]->lookup(st.s, st.t);
}

} // namespace lray
