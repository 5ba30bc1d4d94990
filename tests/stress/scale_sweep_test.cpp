// Robustness suite (issue 8): the same small scene translated by up to 1e5
// and scaled from 1e-4 to 1e4, through both backends. Measures false
// self-shadowing on lit surfaces, checks that an occluder 1e-3 x scale away
// still casts its shadow (the spawn offset does not jump over it), and that
// images of the moved scene match the original.
#include "math/spawn.h"
#include "stress/stress_scenes.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace lray::stress {
namespace {

struct SweepCase {
  double offset;
  double scale;
  /// Largest allowed fraction of lit pixels whose shadow ray is blocked;
  /// < 0: measured and printed only (beyond the targets).
  double selfShadowTarget;
};

// Targets (issue 8): <= 1e-4 of lit pixels up to magnitude 1e3, <= 1e-3 at
// 1e4, and here the same at 1e5. Every case must also keep the shadow of an
// occluder 1e-3 x scale away: far from the origin the backends work in a
// float frame at the eye (geometry/float_frame.h), so the spawn offset is
// that of a scene at the origin.
const SweepCase kCases[] = {
    {0, 1, 1e-4},     {1e2, 1, 1e-4},   {1e3, 1, 1e-4},
    {1e4, 1, 1e-3},   {1e5, 1, 1e-3},    {0, 1e-4, 1e-4},
    {0, 1e-3, 1e-4},  {0, 1e-2, 1e-4},  {0, 1e-1, 1e-4},
    {0, 1e1, 1e-4},   {0, 1e2, 1e-4},   {0, 1e3, 1e-4},
    {0, 1e4, 1e-3},
};

class StressScaleSweep : public ::testing::TestWithParam<BackendKind> {};

TEST_P(StressScaleSweep, LitSurfacesDoNotShadowThemselves) {
  const int width = 256, height = 192;
  for (const SweepCase &c : kCases) {
    StressScene st = makeStressScene(c.offset, c.scale);
    auto accel = makeAccelerator(GetParam(), st.scene);
    std::vector<Ray> rays = cameraRays(st.scene, width, height);
    std::vector<Hit> hits;
    std::vector<int> ids = hitEntities(*accel, rays, &hits);
    size_t lit = 0, falseShadow = 0, nonFinite = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      if (ids[i] < 0) continue;
      const Hit &h = hits[i];
      if (!hitIsFinite(h)) {
        ++nonFinite;
        continue;
      }
      // Lit analytically: the surface faces the light (cosine well above
      // zero) and the unit-frame segment to the light misses every other
      // entity's box widened by 0.05 (the entities are convex, or a torus lit
      // from high above, so a surface facing the light cannot shadow itself).
      Vec3 n = dot(h.ng, rays[i].d) < 0 ? h.ng : -h.ng;
      Vec3 toLight = st.lightWorld - h.p;
      if (dot(n, toLight) <= 0.02 * length(toLight)) continue;
      Vec3 pUnit = st.unitFromWorld.applyPoint(h.p);
      bool blocked = false;
      for (size_t e = 0; e < st.unitBounds.size() && !blocked; ++e) {
        if (e == h.entity) continue;
        Bounds3 b = st.unitBounds[e];
        b.lo = b.lo - Vec3(0.05, 0.05, 0.05);
        b.hi = b.hi + Vec3(0.05, 0.05, 0.05);
        blocked = segmentHitsBox(pUnit, st.lightUnit, b);
      }
      if (blocked) continue;
      ++lit;
      if (accel->occluded(spawnRayTo(h, st.lightWorld))) ++falseShadow;
    }
    double fraction = lit ? static_cast<double>(falseShadow) / static_cast<double>(lit) : 0;
    std::printf("[self-shadow] %-6s offset %-6g scale %-6g: %zu lit pixels, %zu falsely shadowed "
                "(%.2e), target %s\n",
                backendName(GetParam()).c_str(), c.offset, c.scale, lit, falseShadow, fraction,
                c.selfShadowTarget < 0 ? "none" : std::to_string(c.selfShadowTarget).c_str());
    EXPECT_EQ(nonFinite, 0u) << "offset " << c.offset << " scale " << c.scale;
    EXPECT_GT(lit, rays.size() / 4) << "the sweep scene should be mostly lit";
    if (c.selfShadowTarget >= 0) {
      EXPECT_LE(fraction, c.selfShadowTarget) << "offset " << c.offset << " scale " << c.scale;
    }
  }
}

TEST_P(StressScaleSweep, OccluderAtOneThousandthOfScaleCastsShadow) {
  for (const SweepCase &c : kCases) {
    StressScene bare = makeStressScene(c.offset, c.scale, false);
    StressScene plated = makeStressScene(c.offset, c.scale, true);
    auto bareAccel = makeAccelerator(GetParam(), bare.scene);
    auto platedAccel = makeAccelerator(GetParam(), plated.scene);
    struct Probe {
      const char *name;
      double x, z, half;
      uint32_t entity;
    };
    const Probe probes[] = {
        {"cube plate over floor", Plates::kFloorCubeX, Plates::kFloorCubeZ, 0.35,
         StressScene::kFloor},
        {"mesh plate over floor", Plates::kFloorMeshX, Plates::kFloorMeshZ, 0.35,
         StressScene::kFloor},
        {"cube plate over sphere", Plates::kSphereX, Plates::kSphereZ, 0.03, StressScene::kSphere},
    };
    for (const Probe &p : probes) {
      const int n = 20;
      int leaks = 0, probed = 0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          double x = p.x + p.half * (2.0 * i / (n - 1) - 1);
          double z = p.z + p.half * (2.0 * j / (n - 1) - 1);
          Vec3 from = bare.world.applyPoint({x, 5, z});
          Vec3 to = bare.world.applyPoint({x, 0, z});
          Hit h;
          ASSERT_TRUE(bareAccel->intersect({from, to - from}, h)) << p.name;
          ASSERT_EQ(h.entity, p.entity) << p.name;
          ++probed;
          if (!platedAccel->occluded(spawnRayTo(h, plated.lightWorld))) ++leaks;
        }
      std::printf("[occluder] %-6s offset %-6g scale %-6g %-22s: %d of %d shadow rays leak\n",
                  backendName(GetParam()).c_str(), c.offset, c.scale, p.name, leaks, probed);
      EXPECT_EQ(leaks, 0) << p.name << " offset " << c.offset << " scale " << c.scale;
    }
  }
}

TEST_P(StressScaleSweep, MovedSceneRendersTheSameImage) {
  const int width = 96, height = 72;
  // Tolerance: a pixel differs when a channel moves by more than 1/255; at
  // most 0.1 % of pixels (7 of 6912) may. Measured: no pixel differs at
  // all (mean |diff| 0), on both backends: hits are filled in double, and
  // far from the origin Embree works in a float frame next to the scene.
  const double tol = 1.0 / 255, maxFraction = 0.001;
  Film reference = renderChecked(makeStressScene(0, 1).scene, GetParam(), width, height);
  for (const SweepCase &c : kCases) {
    if (c.offset == 0 && c.scale == 1) continue;
    Film film = renderChecked(makeStressScene(c.offset, c.scale).scene, GetParam(), width, height);
    ImageDiff d = compareFilms(reference, film, tol);
    std::printf("[image] %-6s offset %-6g scale %-6g: %.4f of pixels differ by > 1/255, mean "
                "|diff| %.2e\n",
                backendName(GetParam()).c_str(), c.offset, c.scale, d.fractionOver, d.meanAbs);
    if (c.selfShadowTarget >= 0) {
      EXPECT_LE(d.fractionOver, maxFraction) << "offset " << c.offset << " scale " << c.scale;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, StressScaleSweep, ::testing::ValuesIn(kBothBackends),
                         backendParamName);

} // namespace
} // namespace lray::stress
