// Pipeline: shading. The Phong finish of the shading equation: a texture's Finish
// prepared once per frame (Material), and what one unblocked light sample
// adds at a surface point: diffuse N.L plus the specular highlight
// specular * max(0, R.V)^exponent, R the light direction mirrored about N.
#pragma once

#include "math/color.h"
#include "math/vec3.h"
#include "scene/scene.h"

#include <cmath>
#include <cstdint>

namespace lray {

/// A Finish with what shading asks of it per hit precomputed.
struct Material {
  Finish finish;
  uint32_t pigment = 0;
  bool lit = false;      ///< diffuse or specular non-zero and some light exists
  bool reflects = false; ///< reflection > 0
  bool refracts = false; ///< refraction > 0
  bool emits = false;    ///< emission not black
  /// The specular exponent when it is an integer in [0, 1024] (the common
  /// case: powers by squaring instead of std::pow, which took a tenth of
  /// the 2011 examples' shapes.lua at exponent 128), else -1. At most ten
  /// squarings: within about 2^-43 of x^n relative, far below a float
  /// output's step.
  int integerExponent = -1;
  static constexpr double kMaxIntegerExponent = 1024;

  /// `finish` and `pigment` of a texture; `anyLight`: the frame has a light.
  static Material prepare(const Finish &finish, uint32_t pigment, bool anyLight) {
    Material m;
    m.finish = finish;
    m.pigment = pigment;
    m.lit = (finish.diffuse != 0 || finish.specular != 0) && anyLight;
    m.reflects = finish.reflection > 0;
    m.refracts = finish.refraction > 0;
    m.emits = !finish.emission.isBlack();
    double e = finish.exponent;
    if (e >= 0 && e <= kMaxIntegerExponent && e == std::floor(e))
      m.integerExponent = static_cast<int>(e);
    if (!(finish.refractionIndex > 0) || !std::isfinite(finish.refractionIndex))
      m.finish.refractionIndex = 1; // guards the Snell ratio against 0 and NaN
    return m;
  }
};

/// max(0, x)^e, written so that 0^e never becomes inf or NaN.
inline double specularPower(double x, const Material &m) {
  if (!(x > 0)) return m.finish.exponent == 0 ? 1.0 : 0.0;
  int n = m.integerExponent;
  if (n < 0) return std::pow(x, m.finish.exponent);
  double result = 1;
  while (n > 0) {
    if (n & 1) result *= x;
    x *= x;
    n >>= 1;
  }
  return result;
}

/// The light a sample reaching the surface unblocked adds, before the
/// sample's colour: diffuse N.L (`diffuseColor` = pigment * diffuse) plus
/// the specular highlight. N, V, L unit; nl = N.L > 0.
inline Color phongColor(const Vec3 &n, const Vec3 &v, const Vec3 &l, double nl,
                        const Color &diffuseColor, const Material &m) {
  Color c = diffuseColor * nl;
  if (m.finish.specular != 0) {
    Vec3 r = n * (2 * nl) - l;
    double s = m.finish.specular * specularPower(dot(r, v), m);
    c += Color(s, s, s);
  }
  return c;
}

} // namespace lray
