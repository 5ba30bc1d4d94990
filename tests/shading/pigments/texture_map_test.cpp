// Tests for src/shading/pigments/texture_map: each map at hand-computed points.
#include "shading/pigments/texture_map.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

Hit hitAt(const Vec3 &pObject, double u = 0, double v = 0) {
  Hit h;
  h.pObject = pObject;
  h.p = pObject + Vec3(100, 100, 100); // world point must not be what maps read
  h.u = u;
  h.v = v;
  return h;
}

TEST(TextureMap, TextureMap2DIsUv) {
  TextureMap m;
  TexCoord2 st = mapPoint2D(m, hitAt({5, 6, 7}, 0.25, 0.75));
  EXPECT_EQ(st.s, 0.25);
  EXPECT_EQ(st.t, 0.75);
}

TEST(TextureMap, UVMapScalesThenTranslates) {
  TextureMap m;
  m.kind = TextureMap::Kind::UVMap;
  m.scaleS = 2;
  m.scaleT = 4;
  m.translateS = 0.1;
  m.translateT = -0.2;
  TexCoord2 st = mapPoint2D(m, hitAt({}, 0.5, 0.25));
  EXPECT_DOUBLE_EQ(st.s, 1.1);
  EXPECT_DOUBLE_EQ(st.t, 0.8);
}

TEST(TextureMap, SphericalMapMatchesSphereUv) {
  TextureMap m;
  m.kind = TextureMap::Kind::SphericalMap;
  TexCoord2 a = mapPoint2D(m, hitAt({1, 0, 0}));
  EXPECT_DOUBLE_EQ(a.s, 0.5);
  EXPECT_DOUBLE_EQ(a.t, 0.5);
  TexCoord2 b = mapPoint2D(m, hitAt({0, 0, 3}));
  EXPECT_DOUBLE_EQ(b.s, 0.75);
  TexCoord2 c = mapPoint2D(m, hitAt({0, 2, 0}));
  EXPECT_DOUBLE_EQ(c.t, 1.0);
  TexCoord2 d = mapPoint2D(m, hitAt({0, -0.5, 0}));
  EXPECT_DOUBLE_EQ(d.t, 0.0);
  // On the unit sphere it is exactly the sphere's own uv (lua/README.md, "Entities").
  Vec3 p = normalize(Vec3(0.3, -0.4, -0.5));
  TexCoord2 e = mapPoint2D(m, hitAt(p));
  EXPECT_NEAR(e.t, (p.y + 1) / 2, 1e-15);
  TexCoord2 o = mapPoint2D(m, hitAt({0, 0, 0}));
  EXPECT_EQ(o.t, 0.5);
}

TEST(TextureMap, CylindricalMapIsAngleAndHeight) {
  TextureMap m;
  m.kind = TextureMap::Kind::CylindricalMap;
  TexCoord2 a = mapPoint2D(m, hitAt({1, 0.3, 0}));
  EXPECT_DOUBLE_EQ(a.s, 0.0);
  EXPECT_DOUBLE_EQ(a.t, 0.3);
  TexCoord2 b = mapPoint2D(m, hitAt({0, 2, 1}));
  EXPECT_DOUBLE_EQ(b.s, 0.25);
  EXPECT_DOUBLE_EQ(b.t, 2.0);
  TexCoord2 c = mapPoint2D(m, hitAt({0, 0, -1}));
  EXPECT_DOUBLE_EQ(c.s, 0.75);
  TexCoord2 d = mapPoint2D(m, hitAt({-1, 0, 0}));
  EXPECT_DOUBLE_EQ(d.s, 0.5);
}

TEST(TextureMap, TextureMap3DIsObjectPoint) {
  TextureMap m;
  m.kind = TextureMap::Kind::TextureMap3D;
  EXPECT_EQ(mapPoint3D(m, hitAt({1, -2, 3})), Vec3(1, -2, 3));
}

TEST(TextureMap, LinearMapAppliesItsTransform) {
  TextureMap m;
  m.kind = TextureMap::Kind::LinearMap;
  m.transform = Transform::translate({1, 2, 3}) * Transform::scale(2, 2, 2);
  Vec3 q = mapPoint3D(m, hitAt({1, -2, 3}));
  EXPECT_DOUBLE_EQ(q.x, 3);
  EXPECT_DOUBLE_EQ(q.y, -2);
  EXPECT_DOUBLE_EQ(q.z, 9);
}

} // namespace
} // namespace lray
