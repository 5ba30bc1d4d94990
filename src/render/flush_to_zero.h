// Pipeline: render. Denormals are flushed to zero on render threads: they
// cost 100x on x86 and never change a visible value. Everything a render
// computes in parallel sets it first, so a value never depends on which
// thread happened to compute it (a worker that never ran a tile has it off).
#pragma once

#include <xmmintrin.h>

namespace lray {

inline void setFlushToZero() { _mm_setcsr(_mm_getcsr() | 0x8040); }

} // namespace lray
