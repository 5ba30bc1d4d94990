// Checks of sampled distributions shared by the BSDF tests (ggx_test.cpp,
// rough_lobes_test.cpp), as Mitsuba's and pbrt-v4's BSDF tests make them:
// integrals over the hemisphere by quadrature, and Pearson's chi-square of
// sample counts against the counts a density predicts.
#pragma once

#include "math/vec3.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace lray::testing {

/// The integral of g over the hemisphere about +z by the midpoint rule in
/// (cos theta, phi), dense near the pole where narrow lobes live.
template <class F> double hemisphere(F g, int nu = 2000, int nphi = 256) {
  double sum = 0;
  for (int i = 0; i < nu; ++i) {
    // u = cos theta = 1 - x^2 puts most cells near the pole: du = 2x dx.
    const double x = (i + 0.5) / nu, cosT = 1 - x * x, sinT = std::sqrt(1 - cosT * cosT);
    const double du = 2 * x / nu;
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2 * std::numbers::pi * (j + 0.5) / nphi;
      const double dphi = 2 * std::numbers::pi / nphi;
      sum += g(Vec3(sinT * std::cos(phi), sinT * std::sin(phi), cosT)) * du * dphi;
    }
  }
  return sum;
}

/// Pearson's chi-square of samples against expected counts over bins of
/// (cos theta, phi); bins expected to hold fewer than 5 are pooled.
/// Returns the statistic over its critical value at p = 1e-4
/// (Wilson-Hilferty), so < 1 passes.
inline double chiSquareRatio(const std::vector<double> &observed,
                             const std::vector<double> &expected) {
  double chi2 = 0, poolObs = 0, poolExp = 0;
  int dof = -1;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5) {
      poolObs += observed[i];
      poolExp += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (poolExp > 0) {
    chi2 += (poolObs - poolExp) * (poolObs - poolExp) / poolExp;
    ++dof;
  }
  const double z = 3.719, k = dof; // the normal quantile of 1 - 1e-4
  const double critical = k * std::pow(1 - 2 / (9 * k) + z * std::sqrt(2 / (9 * k)), 3);
  return chi2 / critical;
}

} // namespace lray::testing
