// Tests for src/shading/emitters (lua/README.md, "Light transport"): points
// drawn on an emitting mesh spread uniformly over its triangles, wherever
// the triangles are, with the normal and density a hit there has.
#include "shading/emitters.h"
#include "shading/quad_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lray {
namespace {

/// A scene whose only entity is an emitting square, corners (-h, -h, z) to
/// (h, h, z) in world space, facing -z, placed by `placement`.
Scene emittingSquare(double h, double z, const Transform &placement = Transform()) {
  Scene s;
  Pigment p;
  p.pattern = ColorPigment{{1, 1, 1}};
  s.pigments.push_back(p);
  Finish lamp;
  lamp.emission = {2, 2, 2};
  s.textures.push_back({lamp, 0});
  const float fh = static_cast<float>(h), fz = static_cast<float>(z);
  testing::addQuad(s, {Vec3f{-fh, -fh, fz}, {-fh, fh, fz}, {fh, fh, fz}, {fh, -fh, fz}}, 0,
                   placement); // facing -z
  return s;
}

TEST(Emitters, TrianglePointsSpreadUniformlyWhereverTheTriangleIs) {
  // A square across the z axis between 0 and 1: points on it used to be
  // found by a probe ray from the origin along z, which met the square and
  // put every point where the axis crosses it.
  for (const bool placed : {false, true}) {
    SCOPED_TRACE(placed ? "placed by a transform" : "placed by its vertices");
    const Transform placement = placed ? Transform::translate({0, 0, 0.25}) : Transform();
    const double z = placed ? 0.25 : 0.5, h = 0.5;
    const Scene s = emittingSquare(h, z, placement);
    const Emitters emitters(s);
    constexpr int kCount = 4096;
    double sx = 0, sy = 0, sxx = 0, syy = 0;
    for (int i = 0; i < kCount; ++i) {
      Sampler sampler(7, 0, static_cast<uint64_t>(i));
      const Emitters::Sample e = emitters.sample({0, 0, -1}, 0, sampler);
      ASSERT_NEAR(e.p.z, 0.5, 1e-12);
      ASSERT_LE(std::fabs(e.p.x), h + 1e-12);
      ASSERT_LE(std::fabs(e.p.y), h + 1e-12);
      ASSERT_NEAR(e.n.z, -1, 1e-12);
      ASSERT_NEAR(e.pdfArea, 1.0, 1e-12); // one unit of area
      sx += e.p.x;
      sy += e.p.y;
      sxx += e.p.x * e.p.x;
      syy += e.p.y * e.p.y;
    }
    // Uniform over [-h, h]: mean 0 (standard error h / sqrt(3 n)), mean
    // square h^2 / 3 (standard error h^2 * 0.30 / sqrt(n)).
    const double meanError = h / std::sqrt(3.0 * kCount);
    const double squareError = h * h * 0.3 / std::sqrt(kCount);
    EXPECT_NEAR(sx / kCount, 0, 4 * meanError);
    EXPECT_NEAR(sy / kCount, 0, 4 * meanError);
    EXPECT_NEAR(sxx / kCount, h * h / 3, 4 * squareError);
    EXPECT_NEAR(syy / kCount, h * h / 3, 4 * squareError);
  }
}

} // namespace
} // namespace lray
