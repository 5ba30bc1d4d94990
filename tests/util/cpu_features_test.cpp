// Tests for src/util/cpu_features.h: the start-up check's list of what a
// build uses and a CPU lacks, and that the build's own flags are what
// kCompiledCpuFeatures reports.
#include "util/cpu_features.h"

#include <gtest/gtest.h>

#include <string>

namespace lray {
namespace {

TEST(CpuFeatures, NamesWhatTheBuildUsesAndTheCpuLacks) {
  char names[64];
  const unsigned compiled = kCpuAvx | kCpuAvx2 | kCpuAvx512f | kCpuAvx512vl;
  EXPECT_EQ(missingCpuFeatures(compiled, kCpuAvx | kCpuAvx2 | kCpuFma, names, sizeof names), 2u);
  EXPECT_EQ(std::string(names), "avx512f, avx512vl");
  EXPECT_EQ(missingCpuFeatures(compiled, compiled | kCpuBmi2, names, sizeof names), 0u);
  EXPECT_EQ(std::string(names), "");
  EXPECT_EQ(missingCpuFeatures(kCpuSse42 | kCpuAvx512bf16, 0, names, sizeof names), 2u);
  EXPECT_EQ(std::string(names), "sse4.2, avx512bf16");
}

TEST(CpuFeatures, ShortBuffersStayTerminated) {
  char names[8] = "xxxxxxx";
  EXPECT_EQ(missingCpuFeatures(kCpuAvx512f | kCpuAvx512vl, 0, names, sizeof names), 2u);
  EXPECT_EQ(std::string(names), "avx512f"); // 7 characters and the terminator
  char untouched = 'x';
  EXPECT_EQ(missingCpuFeatures(kCpuAvx2, 0, &untouched, 0), 1u);
  EXPECT_EQ(untouched, 'x');
}

TEST(CpuFeatures, ReportsTheFlagsEveryFileIsCompiledWith) {
  // This file has the build's flags, as cpu_target.cpp does.
#ifdef __AVX2__
  EXPECT_NE(kCompiledCpuFeatures & kCpuAvx2, 0u);
#else
  EXPECT_EQ(kCompiledCpuFeatures & kCpuAvx2, 0u);
#endif
#ifdef __AVX512F__
  EXPECT_NE(kCompiledCpuFeatures & kCpuAvx512f, 0u);
#else
  EXPECT_EQ(kCompiledCpuFeatures & kCpuAvx512f, 0u);
#endif
  // The machine running the tests runs the build.
  char names[256];
  EXPECT_EQ(missingCpuFeatures(kCompiledCpuFeatures, presentCpuFeatures(), names, sizeof names),
            0u)
      << names;
  EXPECT_EQ((presentCpuFeatures() & kCpuAvx2) != 0, cpuHasAvx2());
}

} // namespace
} // namespace lray
