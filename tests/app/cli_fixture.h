// Test helpers for the lray and lray-merge binaries: run one with
// arguments (stdout and stderr together), read a file, and a fixture with
// a fresh temporary folder per test.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace lray {
namespace cli_test {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string output; // stdout + stderr
};

/// Runs `binary` (a path) with `args`.
inline Result runBinary(const std::string &binary, const std::string &args) {
  std::string cmd = binary + " " + args + " 2>&1";
  Result r;
  FILE *pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

inline Result runLray(const std::string &args) { return runBinary(LRAY_BINARY, args); }

/// lray-merge, built beside lray.
inline Result runMerge(const std::string &args) {
  return runBinary((std::filesystem::path(LRAY_BINARY).parent_path() / "lray-merge").string(),
                   args);
}

inline std::string readFile(const fs::path &p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class LrayCli : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lray_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path writeScene(const std::string &name, const std::string &text) {
    fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }

  fs::path dir_;
};

} // namespace cli_test
} // namespace lray
