// Pipeline: shared math. Counter-based random numbers: a value is a pure
// function of (seed, index), so renders are identical whatever the thread
// count or tile order, and no state is shared between threads.
#pragma once

#include "math/mix64.h"
#include "math/owen_sobol.h"

#include <cstdint>

namespace lray {

/// A stream of uniform numbers keyed by (frame, pixel, sample): each call to
/// next() consumes one dimension. Cheap to copy; two samplers with the same
/// key produce the same sequence. Independent numbers by default; after
/// stratify(), the dimensions come in pairs, each pair the Owen-scrambled
/// Sobol point of the sample's index with a scramble and shuffle of its own
/// (Burley 2020's padding): a pixel's samples are stratified in every pair
/// of dimensions (the path tracer's light and direction choices), as in
/// pixel position.
class Sampler {
public:
  Sampler() = default;
  Sampler(uint64_t frame, uint64_t pixel, uint64_t sample)
      : Sampler(pixelKey(frame, pixel), sample) {}
  /// The same stream from its pixel's part of the key (pixelKey), which
  /// the tile loop computes once per pixel, not once per sample.
  Sampler(uint64_t pixelKey, uint64_t sample) : key_(mix64(pixelKey ^ sample)) {}
  static uint64_t pixelKey(uint64_t frame, uint64_t pixel) {
    return pixelKeyOf(frameKey(frame), pixel);
  }
  /// pixelKey in two halves: the frame's, the same for all its pixels,
  /// then a pixel's.
  static uint64_t frameKey(uint64_t frame) { return mix64(frame + 0x9e3779b97f4a7c15ULL); }
  static uint64_t pixelKeyOf(uint64_t frameKey, uint64_t pixel) { return mix64(frameKey ^ pixel); }

  /// Stratified dimensions from here on, `index` being the sample's index
  /// among its pixel's and `pixelSeed` the pixel's (the same for all its
  /// samples).
  void stratify(uint32_t index, uint64_t pixelSeed) {
    stratified_ = true;
    index_ = index;
    pixelSeed_ = pixelSeed;
  }

  /// Uniform double in [0, 1).
  double next() {
    if (stratified_) return nextStratified();
    return independent(key_, ++dim_);
  }
  /// The number of dimension `dim` (1, 2, ...) of the stream keyed `key`
  /// before stratify(): what lanes of samplers draw side by side
  /// (shading/light_lanes.cpp).
  static double independent(uint64_t key, uint64_t dim) {
    const uint64_t bits = mix64(key + 0x9e3779b97f4a7c15ULL * dim);
    return static_cast<double>(bits >> 11) * 0x1.0p-53;
  }
  bool stratified() const { return stratified_; }
  /// How many numbers have been drawn; advance(n): n more were drawn
  /// outside (by independent(key(), drawn() + 1), ...).
  uint64_t drawn() const { return dim_; }
  void advance(uint64_t n) { dim_ += n; }
  /// Two numbers that belong together (a point on a light, a direction):
  /// stratified jointly after stratify(); else next() twice.
  void next2D(double &u, double &v) {
    if (stratified_ && (dim_ & 1)) ++dim_; // start a pair of their own
    u = next();
    v = next();
  }
  uint64_t key() const { return key_; }

  /// Which share of an area light's cells this sample takes when a pixel's
  /// samples share the cells out (LightSampling::Spread; the integrator
  /// reduces it modulo the share count). Unused otherwise.
  uint32_t lightStratum = 0;
  /// The sample's time in the open shutter (Ray::time of its camera ray):
  /// moving lights are sampled where they are then.
  float time = 0;

private:
  double nextStratified() {
    if (dim_ & 1) {
      ++dim_;
      return pending_;
    }
    double u;
    owenSobol2D(index_, mix64(pixelSeed_ + 0x9e3779b97f4a7c15ULL * (dim_ / 2 + 1)), u, pending_);
    ++dim_;
    return u;
  }

  uint64_t key_ = 0;
  uint64_t dim_ = 0;
  bool stratified_ = false;
  uint32_t index_ = 0;
  uint64_t pixelSeed_ = 0;
  double pending_ = 0; ///< the pair's second number
};

} // namespace lray
