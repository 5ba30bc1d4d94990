// Pipeline: shared math. Counter-based random numbers: a value is a pure
// function of (seed, index), so renders are identical whatever the thread
// count or tile order, and no state is shared between threads.
#pragma once

#include <cstdint>

namespace lray {

/// A 64-bit mixing function (SplitMix64 finaliser constants, Steele et al. 2014).
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A stream of uniform numbers keyed by (frame, pixel, sample): each call to
/// next() consumes one dimension. Cheap to copy; two samplers with the same
/// key produce the same sequence.
class Sampler {
public:
  Sampler() = default;
  Sampler(uint64_t frame, uint64_t pixel, uint64_t sample)
      : key_(mix64(mix64(mix64(frame + 0x9e3779b97f4a7c15ULL) ^ pixel) ^ sample)) {}

  /// Uniform double in [0, 1).
  double next() {
    uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ULL * ++dim_);
    return static_cast<double>(bits >> 11) * 0x1.0p-53;
  }
  uint64_t key() const { return key_; }

  /// Which share of an area light's cells this sample takes when a pixel's
  /// samples share the cells out (LightSampling::Spread; the integrator
  /// reduces it modulo the share count). Unused otherwise.
  uint32_t lightStratum = 0;

private:
  uint64_t key_ = 0;
  uint64_t dim_ = 0;
};

} // namespace lray
