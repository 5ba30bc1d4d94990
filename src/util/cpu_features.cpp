// Pipeline: shared utilities. cpu_features.h. Compiled for any x86-64 CPU
// whatever the build's flags (src/util/sources.cmake), and calling nothing
// inline that other files compile too: the start-up check below must not
// run an instruction the CPU may lack.
#include "util/cpu_features.h"

#include <cerrno>
#include <cstring>
#include <unistd.h>

namespace lray {

bool cpuHasAvx2() {
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return static_cast<bool>(__builtin_cpu_supports("avx2"));
  }();
  return avx2;
}

namespace {

struct NamedFeature {
  unsigned bit;
  const char *name;
};

constexpr NamedFeature kFeatureNames[] = {
    {kCpuSse42, "sse4.2"},         {kCpuPopcnt, "popcnt"},
    {kCpuAvx, "avx"},              {kCpuAvx2, "avx2"},
    {kCpuFma, "fma"},              {kCpuBmi, "bmi"},
    {kCpuBmi2, "bmi2"},            {kCpuAvx512f, "avx512f"},
    {kCpuAvx512vl, "avx512vl"},    {kCpuAvx512bw, "avx512bw"},
    {kCpuAvx512dq, "avx512dq"},    {kCpuAvx512cd, "avx512cd"},
    {kCpuAvx512ifma, "avx512ifma"}, {kCpuAvx512vbmi, "avx512vbmi"},
    {kCpuAvx512vbmi2, "avx512vbmi2"}, {kCpuAvx512vnni, "avx512vnni"},
    {kCpuAvx512bitalg, "avx512bitalg"}, {kCpuAvx512vpopcntdq, "avx512vpopcntdq"},
    {kCpuAvx512bf16, "avx512bf16"},
};

/// Appends `text` to out[0, size) at *used, keeping it terminated.
void append(char *out, size_t size, size_t *used, const char *text) {
  for (; *text != '\0' && *used + 1 < size; ++text) out[(*used)++] = *text;
  out[*used] = '\0';
}

} // namespace

unsigned presentCpuFeatures() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  // __builtin_cpu_supports takes a literal name.
  unsigned present = 0;
  if (__builtin_cpu_supports("sse4.2")) present |= kCpuSse42;
  if (__builtin_cpu_supports("popcnt")) present |= kCpuPopcnt;
  if (__builtin_cpu_supports("avx")) present |= kCpuAvx;
  if (__builtin_cpu_supports("avx2")) present |= kCpuAvx2;
  if (__builtin_cpu_supports("fma")) present |= kCpuFma;
  if (__builtin_cpu_supports("bmi")) present |= kCpuBmi;
  if (__builtin_cpu_supports("bmi2")) present |= kCpuBmi2;
  if (__builtin_cpu_supports("avx512f")) present |= kCpuAvx512f;
  if (__builtin_cpu_supports("avx512vl")) present |= kCpuAvx512vl;
  if (__builtin_cpu_supports("avx512bw")) present |= kCpuAvx512bw;
  if (__builtin_cpu_supports("avx512dq")) present |= kCpuAvx512dq;
  if (__builtin_cpu_supports("avx512cd")) present |= kCpuAvx512cd;
  if (__builtin_cpu_supports("avx512ifma")) present |= kCpuAvx512ifma;
  if (__builtin_cpu_supports("avx512vbmi")) present |= kCpuAvx512vbmi;
  if (__builtin_cpu_supports("avx512vbmi2")) present |= kCpuAvx512vbmi2;
  if (__builtin_cpu_supports("avx512vnni")) present |= kCpuAvx512vnni;
  if (__builtin_cpu_supports("avx512bitalg")) present |= kCpuAvx512bitalg;
  if (__builtin_cpu_supports("avx512vpopcntdq")) present |= kCpuAvx512vpopcntdq;
  if (__builtin_cpu_supports("avx512bf16")) present |= kCpuAvx512bf16;
  return present;
#else
  return kCompiledCpuFeatures; // no x86 extensions to check
#endif
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
