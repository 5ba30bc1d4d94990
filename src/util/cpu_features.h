// Pipeline: shared utilities. What the CPU can run, asked once: the code
// paths compiled for AVX2 (the kd-tree's triangle prefilter, triangle hits
// in lanes, the tile loop's sample positions) are taken only where it has
// them. And what the build itself was compiled for: with LRAY_NATIVE (the
// default, README.md "Building") every file is compiled for the build
// machine's CPU, and a binary copied to a CPU without those vector units
// stops at start-up with a message saying so, instead of dying on an
// illegal instruction somewhere in a render.
#pragma once

#include <cstddef>

namespace lray {

/// True when the CPU runs AVX2.
bool cpuHasAvx2();

/// Instruction-set extensions a build may be compiled to use, one bit each
/// (the names GCC's __builtin_cpu_supports and the error message use are
/// in cpu_features.cpp).
enum CpuFeature : unsigned {
  kCpuSse42 = 1u << 0,
  kCpuPopcnt = 1u << 1,
  kCpuAvx = 1u << 2,
  kCpuAvx2 = 1u << 3,
  kCpuFma = 1u << 4,
  kCpuBmi = 1u << 5,
  kCpuBmi2 = 1u << 6,
  kCpuAvx512f = 1u << 7,
  kCpuAvx512vl = 1u << 8,
  kCpuAvx512bw = 1u << 9,
  kCpuAvx512dq = 1u << 10,
  kCpuAvx512cd = 1u << 11,
  kCpuAvx512ifma = 1u << 12,
  kCpuAvx512vbmi = 1u << 13,
  kCpuAvx512vbmi2 = 1u << 14,
  kCpuAvx512vnni = 1u << 15,
  kCpuAvx512bitalg = 1u << 16,
  kCpuAvx512vpopcntdq = 1u << 17,
  kCpuAvx512bf16 = 1u << 18,
};

/// The extensions the build's code was compiled to use (cpu_target.cpp,
/// compiled with the build's own flags).
extern const unsigned kCompiledCpuFeatures;

/// The extensions of kCompiledCpuFeatures's list this CPU has.
unsigned presentCpuFeatures();

/// The names of the features in `compiled` but not in `present`, joined by
/// ", " into out (at most size - 1 characters, always terminated); returns
/// how many are missing. Plain C on purpose: it runs before any of the
/// program's own constructors, in code compiled for any x86-64 CPU.
size_t missingCpuFeatures(unsigned compiled, unsigned present, char *out, size_t size);

} // namespace lray
