// Pipeline: shared utilities. cpu_features.h. Compiled for any x86-64 CPU
// whatever the build's flags (src/util/sources.cmake), and calling nothing
// inline that other files compile too: the start-up check below must not
// run an instruction the CPU may lack.
#include "util/cpu_features.h"

#include <cerrno> // program_invocation_short_name
#include <unistd.h>

namespace lray {

namespace {

/// Each feature's bit and its name, as __builtin_cpu_supports takes it (a
/// literal) and the start-up message gives it: the one list both read.
#define LRAY_CPU_FEATURES(X)                                                                       \
  X(kCpuSse42, "sse4.2")                                                                           \
  X(kCpuPopcnt, "popcnt")                                                                          \
  X(kCpuAvx, "avx")                                                                                \
  X(kCpuAvx2, "avx2")                                                                              \
  X(kCpuFma, "fma")                                                                                \
  X(kCpuBmi, "bmi")                                                                                \
  X(kCpuBmi2, "bmi2")                                                                              \
  X(kCpuAvx512f, "avx512f")                                                                        \
  X(kCpuAvx512vl, "avx512vl")                                                                      \
  X(kCpuAvx512bw, "avx512bw")                                                                      \
  X(kCpuAvx512dq, "avx512dq")                                                                      \
  X(kCpuAvx512cd, "avx512cd")                                                                      \
  X(kCpuAvx512ifma, "avx512ifma")                                                                  \
  X(kCpuAvx512vbmi, "avx512vbmi")                                                                  \
  X(kCpuAvx512vbmi2, "avx512vbmi2")                                                                \
  X(kCpuAvx512vnni, "avx512vnni")                                                                  \
  X(kCpuAvx512bitalg, "avx512bitalg")                                                              \
  X(kCpuAvx512vpopcntdq, "avx512vpopcntdq")                                                        \
  X(kCpuAvx512bf16, "avx512bf16")

struct NamedFeature {
  unsigned bit;
  const char *name;
};

#define LRAY_NAMED_FEATURE(bit, name) {bit, name},
constexpr NamedFeature kFeatureNames[] = {LRAY_CPU_FEATURES(LRAY_NAMED_FEATURE)};
#undef LRAY_NAMED_FEATURE

/// Appends `text` to out[0, size) at *used, keeping it terminated.
void append(char *out, size_t size, size_t *used, const char *text) {
  for (; *text != '\0' && *used + 1 < size; ++text) out[(*used)++] = *text;
  out[*used] = '\0';
}

} // namespace

unsigned presentCpuFeatures() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  unsigned present = 0;
#define LRAY_TEST_FEATURE(bit, name)                                                               \
  if (__builtin_cpu_supports(name)) present |= bit;
  LRAY_CPU_FEATURES(LRAY_TEST_FEATURE)
#undef LRAY_TEST_FEATURE
  return present;
#else
  return kCompiledCpuFeatures; // no x86 extensions to check
#endif
}

bool cpuHasAvx2() {
  static const bool avx2 = (presentCpuFeatures() & kCpuAvx2) != 0;
  return avx2;
}

size_t missingCpuFeatures(unsigned compiled, unsigned present, char *out, size_t size) {
  size_t used = 0, missing = 0;
  if (size > 0) out[0] = '\0';
  for (const NamedFeature &f : kFeatureNames) {
    if ((compiled & f.bit) == 0 || (present & f.bit) != 0) continue;
    if (size > 0) {
      if (missing > 0) append(out, size, &used, ", ");
      append(out, size, &used, f.name);
    }
    ++missing;
  }
  return missing;
}

namespace {

/// Before any constructor of the program's own code (priority 101 runs
/// first): a build compiled for another CPU says so and exits 1.
__attribute__((constructor(101))) void refuseAnotherCpu() {
  char names[256];
  if (missingCpuFeatures(kCompiledCpuFeatures, presentCpuFeatures(), names, sizeof names) == 0)
    return;
  char message[768];
  size_t used = 0;
  append(message, sizeof message, &used, program_invocation_short_name);
  append(message, sizeof message, &used,
         ": error: this build was compiled for its build machine's CPU (LRAY_NATIVE, the "
         "default) and uses ");
  append(message, sizeof message, &used, names);
  append(message, sizeof message, &used,
         ", which this CPU lacks. Build LRay on this machine, or configure it with "
         "-DLRAY_NATIVE=OFF for binaries that run on any x86-64 CPU (README.md, "
         "\"Building\").\n");
  ssize_t ignored = write(STDERR_FILENO, message, used);
  (void)ignored;
  _exit(1);
}

} // namespace

} // namespace lray
