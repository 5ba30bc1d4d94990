// Pipeline: shared utilities. kCompiledCpuFeatures (cpu_features.h): the
// vector extensions this file's compiler flags enable, which are every
// file's flags (CMakeLists.txt, LRAY_NATIVE). Data only: it is read by the
// start-up check before anything compiled with these flags runs.
#include "util/cpu_features.h"

namespace lray {

extern const unsigned kCompiledCpuFeatures = 0u
#ifdef __SSE4_2__
                                             | kCpuSse42
#endif
#ifdef __POPCNT__
                                             | kCpuPopcnt
#endif
#ifdef __AVX__
                                             | kCpuAvx
#endif
#ifdef __AVX2__
                                             | kCpuAvx2
#endif
#ifdef __FMA__
                                             | kCpuFma
#endif
#ifdef __BMI__
                                             | kCpuBmi
#endif
#ifdef __BMI2__
                                             | kCpuBmi2
#endif
#ifdef __AVX512F__
                                             | kCpuAvx512f
#endif
#ifdef __AVX512VL__
                                             | kCpuAvx512vl
#endif
#ifdef __AVX512BW__
                                             | kCpuAvx512bw
#endif
#ifdef __AVX512DQ__
                                             | kCpuAvx512dq
#endif
#ifdef __AVX512CD__
                                             | kCpuAvx512cd
#endif
#ifdef __AVX512IFMA__
                                             | kCpuAvx512ifma
#endif
#ifdef __AVX512VBMI__
                                             | kCpuAvx512vbmi
#endif
#ifdef __AVX512VBMI2__
                                             | kCpuAvx512vbmi2
#endif
#ifdef __AVX512VNNI__
                                             | kCpuAvx512vnni
#endif
#ifdef __AVX512BITALG__
                                             | kCpuAvx512bitalg
#endif
#ifdef __AVX512VPOPCNTDQ__
                                             | kCpuAvx512vpopcntdq
#endif
#ifdef __AVX512BF16__
                                             | kCpuAvx512bf16
#endif
    ;

} // namespace lray
