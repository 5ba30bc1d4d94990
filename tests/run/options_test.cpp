// Tests for src/run/options: the command line of README.md, "The `lray` command".
#include "run/options.h"
#include "app/app.h"
#include "render/backends.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <new>
#include <stdexcept>
#include <vector>

namespace lray {
namespace {

ParseResult parse(std::vector<const char *> args) {
  args.insert(args.begin(), "lray");
  return parseOptions(static_cast<int>(args.size()), args.data());
}

TEST(Options, Defaults) {
  ParseResult r = parse({"scene.lua", "out"});
  ASSERT_TRUE(r.options);
  EXPECT_EQ(r.options->scenePath, "scene.lua");
  EXPECT_EQ(r.options->outDir, "out");
  EXPECT_EQ(r.options->backend, BackendKind::Embree);
  EXPECT_EQ(r.options->format, ImageFormat::Png);
  EXPECT_EQ(r.options->threads, 0);
  EXPECT_FALSE(r.options->firstFrame);
  EXPECT_DOUBLE_EQ(r.options->scriptTimeout, 60);
}

TEST(Options, AllOptions) {
  ParseResult r = parse({"s.lua", "o", "--backend", "kdtree", "--threads", "2", "--frames", "3:7",
                         "--width", "64", "--height", "48", "--samples", "3", "--format", "exr",
                         "--linear", "--quiet", "--stats", "st.json", "--unsafe",
                         "--script-timeout", "5", "--max-pixels", "1000"});
  ASSERT_TRUE(r.options) << r.message;
  const Options &o = *r.options;
  EXPECT_EQ(o.backend, BackendKind::KdTree);
  EXPECT_EQ(o.threads, 2);
  EXPECT_EQ(*o.firstFrame, 3);
  EXPECT_EQ(*o.lastFrame, 7);
  EXPECT_EQ(*o.width, 64);
  EXPECT_EQ(*o.height, 48);
  EXPECT_EQ(*o.samples, 3);
  EXPECT_EQ(o.format, ImageFormat::Exr);
  EXPECT_TRUE(o.linear);
  EXPECT_TRUE(o.quiet);
  EXPECT_TRUE(o.unsafe);
  EXPECT_EQ(o.statsPath, "st.json");
  EXPECT_DOUBLE_EQ(o.scriptTimeout, 5);
  EXPECT_DOUBLE_EQ(o.maxPixels, 1000);
}

TEST(Options, SingleFrame) {
  ParseResult r = parse({"s.lua", "o", "--frames", "4"});
  ASSERT_TRUE(r.options);
  EXPECT_EQ(*r.options->firstFrame, 4);
  EXPECT_EQ(*r.options->lastFrame, 4);
}

TEST(Options, UsageErrorsExitWithTwo) {
  for (auto args : std::vector<std::vector<const char *>>{
           {"s.lua"},
           {"s.lua", "o", "--backend", "bvh"},
           {"s.lua", "o", "--frames", "7:3"},
           {"s.lua", "o", "--frames", "a:b"},
           {"s.lua", "o", "--threads", "0"},
           {"s.lua", "o", "--width", "-5"},
           {"s.lua", "o", "--format", "jpg"},
           {"s.lua", "o", "--bogus"}}) {
    ParseResult r = parse(args);
    EXPECT_FALSE(r.options) << args.back();
    EXPECT_EQ(r.exitCode, 2) << args.back();
    EXPECT_FALSE(r.message.empty());
  }
}

TEST(Options, HelpAndVersionExitWithZero) {
  ParseResult h = parse({"--help"});
  EXPECT_EQ(h.exitCode, 0);
  EXPECT_NE(h.message.find("--backend"), std::string::npos);
  EXPECT_NE(h.message.find("Examples"), std::string::npos);
  ParseResult v = parse({"--version"});
  EXPECT_EQ(v.exitCode, 0);
  EXPECT_NE(v.message.find("lray "), std::string::npos);
}

TEST(Options, UsageMessagesAreOneReadableLine) {
  auto message = [](std::vector<const char *> args) { return parse(args).message; };
  for (const char *option : {"--threads", "--width", "--height", "--samples", "--script-timeout",
                             "--max-pixels"}) {
    std::string m = message({"s.lua", "o", option, "0"});
    EXPECT_EQ(m, std::string("lray: error: ") + option +
                     ": expects a positive number, got '0' (run 'lray --help' for usage)");
  }
  EXPECT_EQ(message({"s.lua", "o", "--backend", "bvh"}),
            "lray: error: --backend: unknown value 'bvh' (expected embree or kdtree; run 'lray "
            "--help' for usage)");
  EXPECT_EQ(message({"s.lua", "o", "--format", "JPG"}),
            "lray: error: --format: unknown value 'jpg' (expected png, tga or exr; run 'lray "
            "--help' for usage)");
  // Names in any case; --help shows no argument-library internals.
  ParseResult r = parse({"s.lua", "o", "--backend", "KdTree", "--format", "EXR"});
  ASSERT_TRUE(r.options) << r.message;
  EXPECT_EQ(r.options->backend, BackendKind::KdTree);
  EXPECT_EQ(r.options->format, ImageFormat::Exr);
  std::string help = message({"--help"});
  EXPECT_EQ(help.find("->"), std::string::npos) << help;
  EXPECT_EQ(help.find("ENUM"), std::string::npos) << help;
}

// The last-resort handler never shows C++ library names to the user.
TEST(UnexpectedError, IsDescribedWithoutLibraryNames) {
  EXPECT_EQ(describeUnexpectedError(std::bad_alloc()), "out of memory");
  EXPECT_EQ(describeUnexpectedError(std::bad_array_new_length()), "out of memory");
  EXPECT_EQ(describeUnexpectedError(std::length_error("vector::_M_default_append")),
            "a size too large to allocate");
  const std::string range = describeUnexpectedError(
      std::out_of_range("std::vector::_M_range_check: __n (which is 5) >= this->size()"));
  EXPECT_EQ(range.find("std::"), std::string::npos) << range;
  EXPECT_EQ(range.rfind("internal error (", 0), 0u) << range;
  const std::string fsError = describeUnexpectedError(std::filesystem::filesystem_error(
      "cannot create directory", "/no/such", std::make_error_code(std::errc::permission_denied)));
  EXPECT_NE(fsError.find("/no/such"), std::string::npos) << fsError;
  const std::string system = describeUnexpectedError(
      std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again)));
  EXPECT_EQ(system.rfind("the system refused", 0), 0u) << system;
  // A thread refused (std::thread's code, TBB's worker pool's text): the
  // user hears that memory may be short, not "internal error".
  EXPECT_NE(system.find("not enough memory"), std::string::npos) << system;
  const std::string pool = describeUnexpectedError(
      std::runtime_error("pthread_create has failed: Resource temporarily unavailable"));
  EXPECT_EQ(pool, "the system refused to start a thread (not enough memory, or too many "
                  "threads): Resource temporarily unavailable");
  const std::string denied = describeUnexpectedError(
      std::system_error(std::make_error_code(std::errc::permission_denied)));
  EXPECT_EQ(denied.rfind("the system refused: ", 0), 0u) << denied;
}

} // namespace
} // namespace lray
