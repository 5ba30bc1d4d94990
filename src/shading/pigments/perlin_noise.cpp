// Pipeline: shading. Improved noise after Perlin (2002): a permutation of
// 0..255 hashes each lattice corner to one of 12 gradient directions (the
// edge midpoints of a cube, padded to 16 so a 4-bit hash picks them without
// a modulo), blended with the quintic fade 6t^5 - 15t^4 + 10t^3.
#include "shading/pigments/perlin_noise.h"

#include "math/random.h"

#include <array>
#include <cmath>
#include <cstdint>

namespace lray {
namespace {

/// The permutation doubled to 512 entries so corner hashes need no wrap.
/// It is a fixed Fisher-Yates shuffle of 0..255 driven by mix64, computed at
/// compile time: the same on every platform and run.
constexpr std::array<uint8_t, 512> makePermutation() {
  std::array<uint8_t, 256> p{};
  for (int i = 0; i < 256; ++i) p[i] = static_cast<uint8_t>(i);
  for (int i = 255; i > 0; --i) {
    uint64_t r = mix64(0x4c52617950657231ULL + static_cast<uint64_t>(i));
    int j = static_cast<int>(r % static_cast<uint64_t>(i + 1));
    uint8_t tmp = p[i];
    p[i] = p[j];
    p[j] = tmp;
  }
  std::array<uint8_t, 512> doubled{};
  for (int i = 0; i < 512; ++i) doubled[i] = p[i & 255];
  return doubled;
}

constexpr std::array<uint8_t, 512> kPerm = makePermutation();

/// The 12 cube-edge directions, then 4 of them repeated (Perlin 2002, sec. 3).
constexpr double kGrad[16][3] = {
    {1, 1, 0},  {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
    {1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1},  {0, 1, -1}, {0, -1, -1},
    {1, 1, 0},  {0, -1, 1}, {-1, 1, 0}, {0, -1, -1}};

inline double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
inline double lerp(double t, double a, double b) { return a + t * (b - a); }

inline double gradDot(int hash, double x, double y, double z) {
  const double *g = kGrad[hash & 15];
  return g[0] * x + g[1] * y + g[2] * z;
}

/// Lattice cell index modulo 256, safe for any finite coordinate (no
/// float-to-int overflow for huge values).
inline int cellIndex(double floored) {
  return static_cast<int>(floored - 256.0 * std::floor(floored / 256.0)) & 255;
}

} // namespace

double perlinNoise(const Vec3 &p) {
  if (!isFinite(p)) return 0;
  double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  int X = cellIndex(fx), Y = cellIndex(fy), Z = cellIndex(fz);
  double x = p.x - fx, y = p.y - fy, z = p.z - fz;
  double u = fade(x), v = fade(y), w = fade(z);

  int a = kPerm[X] + Y, aa = kPerm[a] + Z, ab = kPerm[a + 1] + Z;
  int b = kPerm[X + 1] + Y, ba = kPerm[b] + Z, bb = kPerm[b + 1] + Z;

  double x00 = lerp(u, gradDot(kPerm[aa], x, y, z), gradDot(kPerm[ba], x - 1, y, z));
  double x10 = lerp(u, gradDot(kPerm[ab], x, y - 1, z), gradDot(kPerm[bb], x - 1, y - 1, z));
  double x01 =
      lerp(u, gradDot(kPerm[aa + 1], x, y, z - 1), gradDot(kPerm[ba + 1], x - 1, y, z - 1));
  double x11 = lerp(u, gradDot(kPerm[ab + 1], x, y - 1, z - 1),
                    gradDot(kPerm[bb + 1], x - 1, y - 1, z - 1));
  return lerp(w, lerp(v, x00, x10), lerp(v, x01, x11));
}

double turbulence(const Vec3 &p, double size) {
  double sum = 0;
  double scale = 1; // 2^-k
  for (int k = 0; k < 32 && scale >= size; ++k) {
    sum += std::fabs(perlinNoise(p / scale)) * scale;
    scale *= 0.5;
  }
  return sum;
}

} // namespace lray
