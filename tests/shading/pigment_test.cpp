// Tests for src/shading/pigment: every pigment kind at hand-computed points.
#include "shading/pigment.h"

#include "shading/pigments/perlin_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lray {
namespace {

const Color kRed{1, 0, 0}, kGreen{0, 1, 0};

void expectColor(const Color &a, const Color &b, double tol = 1e-12) {
  EXPECT_NEAR(a.r, b.r, tol);
  EXPECT_NEAR(a.g, b.g, tol);
  EXPECT_NEAR(a.b, b.b, tol);
}

Hit hitAt(const Vec3 &pObject, double u = 0, double v = 0) {
  Hit h;
  h.pObject = pObject;
  h.u = u;
  h.v = v;
  return h;
}

Pigment colorPigment(const Color &c) {
  Pigment p;
  p.pattern = ColorPigment{c};
  return p;
}

/// [0] red, [1] green, [2] a checker of the given kind over them.
template <class Checker> std::vector<Pigment> checkerTable() {
  Pigment checker;
  checker.pattern = Checker{0, 1};
  if (Checker::kDimensions == 3) checker.map.kind = TextureMap::Kind::TextureMap3D;
  return {colorPigment(kRed), colorPigment(kGreen), checker};
}

Color eval(const std::vector<Pigment> &table, uint32_t index, const Hit &hit) {
  PigmentTable t{table.data(), table.size(), nullptr, 0};
  return evaluatePigment(t, index, hit);
}

TEST(Pigment, ColorIsConstant) {
  std::vector<Pigment> t{colorPigment({0.1, 0.2, 0.3})};
  EXPECT_EQ(eval(t, 0, hitAt({9, 9, 9}, 0.4, 0.6)), Color(0.1, 0.2, 0.3));
}

TEST(Pigment, Checker2DParity) {
  auto t = checkerTable<CheckerPigment2D>();
  EXPECT_EQ(eval(t, 2, hitAt({}, 0.25, 0.25)), kRed);
  EXPECT_EQ(eval(t, 2, hitAt({}, 0.75, 0.75)), kRed);
  EXPECT_EQ(eval(t, 2, hitAt({}, 0.75, 0.25)), kGreen);
  EXPECT_EQ(eval(t, 2, hitAt({}, 0.25, 0.75)), kGreen);
  // Repeats every 1 in s and t.
  EXPECT_EQ(eval(t, 2, hitAt({}, 3.25, -6.75)), kRed);
  EXPECT_EQ(eval(t, 2, hitAt({}, 3.75, -6.75)), kGreen);
  // Negative coordinates: frac(-0.25) = 0.75.
  EXPECT_EQ(eval(t, 2, hitAt({}, -0.25, -0.25)), kRed);
  EXPECT_EQ(eval(t, 2, hitAt({}, -0.25, 0.25)), kGreen);
  EXPECT_EQ(eval(t, 2, hitAt({}, -0.75, -0.75)), kRed);
  EXPECT_EQ(eval(t, 2, hitAt({}, -0.75, -0.25)), kGreen);
}

TEST(Pigment, Checker2DUsesItsMap) {
  auto t = checkerTable<CheckerPigment2D>();
  t[2].map.kind = TextureMap::Kind::UVMap;
  t[2].map.translateS = 0.5;
  EXPECT_EQ(eval(t, 2, hitAt({}, 0.25, 0.25)), kGreen);
}

TEST(Pigment, Checker3DParityIncludingNegatives) {
  auto t = checkerTable<CheckerPigment3D>();
  EXPECT_EQ(eval(t, 2, hitAt({0.5, 0.5, 0.5})), kRed);     // 0
  EXPECT_EQ(eval(t, 2, hitAt({1.5, 0.5, 0.5})), kGreen);   // 1
  EXPECT_EQ(eval(t, 2, hitAt({-0.5, 0.5, 0.5})), kGreen);  // -1
  EXPECT_EQ(eval(t, 2, hitAt({-0.5, -0.5, 0.5})), kRed);   // -2
  EXPECT_EQ(eval(t, 2, hitAt({-0.5, -0.5, -0.5})), kGreen); // -3
  EXPECT_EQ(eval(t, 2, hitAt({-1.5, -2.5, 0.5})), kGreen);  // -5
  EXPECT_EQ(eval(t, 2, hitAt({-1e-12, 0.5, 0.5})), kGreen); // just below 0
}

TEST(Pigment, NestedCheckers) {
  auto t = checkerTable<CheckerPigment2D>();
  Pigment outer;
  CheckerPigment3D &checker = outer.pattern.emplace<CheckerPigment3D>();
  outer.map.kind = TextureMap::Kind::TextureMap3D;
  checker.pigment1 = 2; // the 2-D checker
  checker.pigment2 = 0; // red
  t.push_back(outer);
  EXPECT_EQ(eval(t, 3, hitAt({0.5, 0.5, 0.5}, 0.75, 0.25)), kGreen);
  EXPECT_EQ(eval(t, 3, hitAt({1.5, 0.5, 0.5}, 0.75, 0.25)), kRed);
}

TEST(Pigment, MarbleAtLatticePointsHasNoTurbulence) {
  Pigment m;
  MarblePigment3D &marble = m.pattern.emplace<MarblePigment3D>();
  marble.color1 = {1, 0, 0};
  marble.color2 = {0, 0, 1};
  m.map.kind = TextureMap::Kind::TextureMap3D;
  // turb is 0 at integer points, so t = p . frequency = 5 + 10 + 15 = 30.
  Color c = eval({m}, 0, hitAt({1, 2, 3}));
  double a = std::fabs(std::sin(30.0));
  expectColor(c, {a, 0, 1 - a});
}

TEST(Pigment, MarbleAddsScaledTurbulence) {
  Pigment m;
  MarblePigment3D &marble = m.pattern.emplace<MarblePigment3D>();
  marble.frequency = {1, 2, 3};
  marble.power = 3;
  marble.size = 0.1;
  m.map.kind = TextureMap::Kind::TextureMap3D;
  Vec3 p{0.3, 0.6, -0.2};
  double t = 0.3 + 1.2 - 0.6 + 3 * turbulence(p, 0.1);
  double a = std::fabs(std::sin(t));
  expectColor(eval({m}, 0, hitAt(p)), Color(0, 0, 0) * a + Color(1, 1, 1) * (1 - a));
}

TEST(Pigment, WoodRingsAboutZ) {
  Pigment w;
  WoodPigment3D &wood = w.pattern.emplace<WoodPigment3D>();
  wood.frequency = {1, 1, 1};
  wood.color1 = {1, 1, 0};
  wood.color2 = {0, 0, 0};
  w.map.kind = TextureMap::Kind::TextureMap3D;
  // sqrt(3^2 + 4^2) = 5; integer point so turb = 0; z does not enter the radius.
  double a = std::fabs(std::sin(5.0));
  expectColor(eval({w}, 0, hitAt({3, 4, 0})), {a, a, 0});
  expectColor(eval({w}, 0, hitAt({3, 4, 7})), {a, a, 0});
  // A negative frequency must not produce NaN.
  wood.frequency = {-1, -1, 1};
  EXPECT_TRUE(isFinite(eval({w}, 0, hitAt({3.3, 4.1, 0.2}))));
}

TEST(Pigment, LinearMapMovesThePattern) {
  auto t = checkerTable<CheckerPigment3D>();
  t[2].map.kind = TextureMap::Kind::LinearMap;
  t[2].map.transform = Transform::translate({1, 0, 0});
  EXPECT_EQ(eval(t, 2, hitAt({0.5, 0.5, 0.5})), kGreen);
}

TEST(Pigment, ImageWithoutLoadedImageIsBlack) {
  Pigment p;
  p.pattern = ImagePigment2D{3};
  EXPECT_EQ(eval({p}, 0, hitAt({}, 0.5, 0.5)), Color(0, 0, 0));
}

TEST(Pigment, ImageLooksUpMappedCoordinates) {
  TextureImage img;
  img.width = 2;
  img.height = 1;
  img.rgb = {1, 0, 0, 0, 0, 1}; // left red, right blue
  const TextureImage *images[] = {&img};
  Pigment p;
  p.pattern = ImagePigment2D{0};
  PigmentTable table{&p, 1, images, 1};
  expectColor(evaluatePigment(table, 0, hitAt({}, 0.25, 0.5)), {1, 0, 0});
  expectColor(evaluatePigment(table, 0, hitAt({}, 0.75, 0.5)), {0, 0, 1});
  expectColor(evaluatePigment(table, 0, hitAt({}, 0.5, 0.5)), {0.5, 0, 0.5});
}

} // namespace
} // namespace lray
