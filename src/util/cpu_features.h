// Pipeline: shared utilities. What the CPU can run, asked once: the code
// paths compiled for AVX2 (the kd-tree's triangle prefilter, triangle hits
// in lanes, the tile loop's sample positions) are taken only where it has
// them.
#pragma once

namespace lray {

/// True when the CPU runs AVX2.
bool cpuHasAvx2();

} // namespace lray
