// Pipeline: shading. The dielectric Fresnel reflectance (lua/README.md,
// "The shading equation": Finish.fresnel): the share of light a smooth
// boundary between two indices reflects, unpolarised.
#pragma once

#include <algorithm>
#include <cmath>

namespace lray {

/// F for a ray meeting the boundary at cosI = cos(angle to the normal) in
/// [0, 1], going from index n1 into index n2, eta = n1 / n2. 1 under total
/// internal reflection.
inline double fresnelReflectance(double cosI, double eta) {
  cosI = std::clamp(cosI, 0.0, 1.0);
  const double sin2T = eta * eta * (1 - cosI * cosI);
  if (sin2T >= 1) return 1;
  const double cosT = std::sqrt(1 - sin2T);
  const double rs = (eta * cosI - cosT) / (eta * cosI + cosT);
  const double rp = (cosI - eta * cosT) / (cosI + eta * cosT);
  return 0.5 * (rs * rs + rp * rp);
}

} // namespace lray
