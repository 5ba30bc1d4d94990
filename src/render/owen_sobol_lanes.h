// Pipeline: render. The tile loop's pixel positions eight at a time:
// owenSobol2DReversed (owen_sobol.h) for up to eight pixels at one sample
// index, in AVX2 lanes where the CPU has them. The bit reversals and hash
// multiplications of one position are most of a camera sample's own cost
// on a simple scene (bench/README.md, "Throughput"); eight lanes take them
// at once. The values are the same bits either way.
#pragma once

#include "math/owen_sobol.h"

#include <cstddef>
#include <cstdint>

namespace lray {

constexpr size_t kOwenLanes = 8;

/// The scrambles of kOwenLanes pixels as three rows of their
/// OwenScramble fields (what the lanes load): each pointer reads
/// kOwenLanes values, those past the pixels in use included.
struct OwenRows {
  const uint32_t *shuffle, *sx, *sy;
};

/// Scrambles gathered lane by lane, for pixels whose own rows are not
/// consecutive.
struct OwenLanes {
  uint32_t shuffle[kOwenLanes] = {}, sx[kOwenLanes] = {}, sy[kOwenLanes] = {};

  void set(size_t lane, const OwenScramble &s) {
    shuffle[lane] = s.shuffle;
    sx[lane] = s.sx;
    sy[lane] = s.sy;
  }
  OwenRows rows() const { return {shuffle, sx, sy}; }
};

/// u[k], v[k] = owenSobol2DReversed(reversedIndex, lane k's scramble) for
/// k < count (at most kOwenLanes; lanes past count are computed from
/// whatever they hold and not written).
void owenSobol2DLanes(uint32_t reversedIndex, const OwenRows &rows, size_t count, double *u,
                      double *v);

namespace detail {
/// owenSobol2DLanes with the path chosen: AVX2 lanes (`avx2`, only where
/// the CPU has it) or one position at a time. Tests compare the two.
void owenSobol2DLanes(uint32_t reversedIndex, const OwenRows &rows, size_t count, double *u,
                      double *v, bool avx2);
} // namespace detail

} // namespace lray
