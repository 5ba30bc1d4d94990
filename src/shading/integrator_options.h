// Pipeline: shading. What a frame's settings tell an integrator (the
// Whitted one of integrator.h and the path tracer of path_integrator.h
// take the same, so the tile loop constructs either alike).
#pragma once

#include <cstdint>

namespace lray {

struct IntegratorOptions {
  /// > 1: a pixel's samples share each area light's cells out (Integrator).
  uint32_t lightShares = 1;
  /// Skip shadow rays nothing can block (shading/shadow_shaft.h).
  bool shadowSkips = true;
  /// The path tracer's most scattering events per path (the Whitted
  /// integrator's depth is fixed: Integrator::kMaxDepth).
  int maxDepth = 8;
  /// The path tracer scales a sample down to this largest component (--clamp; 0: never).
  double clamp = 0;
};

} // namespace lray
