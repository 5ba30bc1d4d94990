// Pipeline: geometry. The hit record every backend fills in the same way
// (the shapes' own code computes it, so backends cannot disagree).
#pragma once

#include "math/vec3.h"

#include <cstdint>

namespace lray {

/// The closest intersection of a ray with the scene.
struct Hit {
  double t = 0;            ///< ray parameter of the hit (units of |ray.d|)
  uint32_t entity = 0;     ///< index into Scene::entities
  uint32_t primitive = 0;  ///< triangle index for meshes, 0 for analytic shapes
  Vec3 p;                  ///< hit point, world space
  Vec3 pObject;            ///< hit point, entity object space (before worldFromObject)
  Vec3 ng; ///< geometric normal, world space, unit, outward (not flipped to face the ray)
  Vec3 ns; ///< shading normal, world space, unit, outward (same side as ng)
  double u = 0, v = 0; ///< surface parameterisation (lua/README.md, "Entities")
  double pError = 0;   ///< conservative bound on the absolute error of p, per component
  float time = 0;      ///< the time of the ray that found it (Ray::time)
};

} // namespace lray
