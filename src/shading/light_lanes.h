// Pipeline: shading. The light loop's arithmetic for one cell of a Light
// (lua/README.md, "Lights") over a tile's lit points, in structure-of-
// arrays lanes: where each point's sample lies, its direction and N.L, its
// shadow ray and the Phong colour it brings if nothing blocks it. Four
// points at a time in AVX2 lanes where the CPU has them: an area light's
// cells are most of a render's time where one lights the scene
// (bench/README.md, "Throughput"), and a point's sample took a square root
// and three divisions one after another. The values are the same bits
// either way, and the same as integrator_impl.h's loop for one point.
#pragma once

#include "math/bounds.h"
#include "math/random.h"
#include "math/spawn.h"
#include "math/vec3.h"
#include "shading/lights/light.h"
#include "shading/phong.h"

#include <cstddef>
#include <cstdint>

namespace lray {

/// Lanes begin <= j < end (begin a multiple of 4): the points a round
/// works on (the integrator gives all of a tile's).
struct LaneSpan {
  size_t begin, end;
};

/// The lit points of a tile (set once per tile) and one round's samples,
/// one array per coordinate; lane j is point j.
struct LightLanes {
  static constexpr size_t kMax = 256; ///< Integrator::kMaxTileRays
  size_t count = 0;

  // Per point.
  uint32_t point[kMax]; ///< its index in the tile's hits
  const Material *material[kMax];
  float time[kMax];
  alignas(32) double px[kMax], py[kMax], pz[kMax]; ///< hit point
  alignas(32) double nx[kMax], ny[kMax], nz[kMax]; ///< N, facing the ray
  alignas(32) double gx[kMax], gy[kMax], gz[kMax]; ///< geometric normal
  alignas(32) double vx[kMax], vy[kMax], vz[kMax]; ///< V
  alignas(32) double fx[kMax], fy[kMax], fz[kMax]; ///< origin of rays on ng's side
  alignas(32) double bx[kMax], by[kMax], bz[kMax]; ///< origin of the others
  alignas(32) double dr[kMax], dg[kMax], db[kMax]; ///< pigment * diffuse
  alignas(32) double specular[kMax];
  alignas(32) int32_t exponent[kMax]; ///< Material::integerExponent (-1: std::pow)

  // Per round, in: the sample's place on the grid, in cells (col + jitter,
  // row + jitter), and whether the point takes a sample this round (with
  // spread light sampling, a point's share may have no cell left).
  alignas(32) double ax[kMax], az[kMax];
  alignas(32) uint8_t active[kMax];
  // The points' samplers while the lanes draw their jitter (loadSamplers
  // to storeSamplers): key and numbers drawn.
  alignas(32) uint64_t key[kMax], drawn[kMax];

  // Per round, out (lanes with valid[j] only): the shadow ray (tMax 1) and
  // the colour before the light's, pigment * diffuse * N.L plus the
  // highlight.
  uint8_t valid[kMax]; ///< the sample lies off the point and in front of it
  uint8_t clearRay[kMax]; ///< scratch for the caller: which lanes' rays are clear
  uint32_t rayLane[kMax]; ///< the lane of each ray writeRays wrote
  alignas(32) double ox[kMax], oy[kMax], oz[kMax];
  alignas(32) double dx[kMax], dy[kMax], dz[kMax];
  alignas(32) double cr[kMax], cg[kMax], cb[kMax];
  alignas(32) double rv[kMax]; ///< R.V, kept for the lanes std::pow finishes
  /// The bits of the largest integer exponent of a lane with a highlight.
  int powerBits = 0;

  /// The light at each point so far (addLit adds to it; the integrator
  /// loads and stores it around a light's rounds).
  alignas(32) double sr[kMax], sg[kMax], sb[kMax];

  /// Per point, over one light's rounds (the integrator's to keep): the
  /// analytic entity that blocked its last blocked shadow ray, or
  /// kNoEntity. A neighbouring cell's ray is likely blocked by it too, so
  /// it is tested first.
  uint32_t occluder[kMax];
  /// Whether some point's occluder is set (none is in a scene of meshes).
  bool anyOccluder = false;

  /// No points yet.
  void clear() {
    count = 0;
    powerBits = 0;
  }
  /// The shadow rays of the valid lanes in `span`, to rays[first, first +
  /// n) in lane order (rayLane[k]: ray k's lane); returns n.
  size_t writeRays(LaneSpan span, Ray *rays, size_t first = 0);
  /// Lane `count` becomes this point (hit, its spawn origins and surface
  /// N, V and pigment, material m).
  void add(uint32_t index, const Hit &hit, const SpawnOrigins &origins, const Vec3 &n,
           const Vec3 &v, const Color &pigment, const Material &m);
};

/// Whether the lanes can draw their points' jitter themselves (every
/// point's sampler is an independent stream, not stratified): then they
/// take the samplers' keys and counts, for placeLanes.
bool loadSamplers(LightLanes &lanes, const Sampler *samplers);
/// The numbers placeLanes drew, counted in the points' samplers.
void storeSamplers(const LightLanes &lanes, Sampler *samplers);
/// ax and az of the lanes in `span` for cell (row, col) of `light`: what
/// light.place gives with each point's sampler (after loadSamplers).
void placeLanes(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int row, int col);
/// The same for round `round` of spread light sampling in `shares` shares
/// (lua/README.md, "--light-sampling"): each lane's cell is round * shares
/// + its sampler's lightStratum % shares, and a lane past the last cell is
/// not active and draws nothing. Without loadSamplers (`inLanes` false),
/// the samplers draw one by one.
void placeSpread(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int round,
                 int shares, Sampler *samplers, bool inLanes);

/// What a round found over the valid lanes.
struct LightRound {
  size_t valid = 0;
  /// Whether every valid ray's origin and end (o + d) is finite: then
  /// `from` and `to` are the boxes around them (shaftEnds's values; a zero
  /// bound may differ in sign, which the shaft test cannot tell apart).
  bool finite = true;
  Bounds3 from, to;
};

/// One round: the outputs of the lanes in `span` from their points and
/// (ax, az).
LightRound lightLanesRound(LightLanes &lanes, LaneSpan span, const LightGrid &grid);

/// A round's colours: lightLanesRound's cr, cg and cb, or a copy held
/// (ShadowBatch).
struct LitColours {
  const double *r, *g, *b;
};

/// A round's light at the lanes j in `span` where add[j] (the valid ones
/// whose shadow ray is clear): sums += lightColor * c * weight (c: the
/// round's colours; the weight of a spread share, 1 is exact).
void addLit(LightLanes &lanes, LaneSpan span, const LitColours &c, const Color &lightColor,
            double weight, const uint8_t *add);
/// The same with the colours of the round just taken.
inline void addLit(LightLanes &lanes, LaneSpan span, const Color &lightColor, double weight,
                   const uint8_t *add) {
  addLit(lanes, span, {lanes.cr, lanes.cg, lanes.cb}, lightColor, weight, add);
}

namespace detail {
/// lightLanesRound and addLit with the path chosen: AVX2 lanes (`avx2`,
/// only where the CPU has it) or one lane at a time. Tests compare the two.
LightRound lightLanesRound(LightLanes &lanes, LaneSpan span, const LightGrid &grid, bool avx2);
void addLit(LightLanes &lanes, LaneSpan span, const LitColours &c, const Color &lightColor,
            double weight, const uint8_t *add, bool avx2);
void placeLanes(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int row, int col,
                bool avx2);
void placeSpread(LightLanes &lanes, LaneSpan span, const Light::Sampler &light, int round,
                 int shares, Sampler *samplers, bool inLanes, bool avx2);
} // namespace detail

} // namespace lray
