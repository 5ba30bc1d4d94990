// Pipeline: render. Denormals are flushed to zero on render threads: they
// cost 100x on x86 and never change a visible value. Everything a render
// computes in parallel sets it first, so a value never depends on which
// thread happened to compute it (TBB runs a task with the floating-point
// settings it chooses, not those a tile left behind).
#pragma once

#include <xmmintrin.h>

namespace lray {

inline void setFlushToZero() { _mm_setcsr(_mm_getcsr() | 0x8040); }

} // namespace lray
