// The look at an EXR's header before OpenEXR opens it (shading/exr_header):
// what LRay writes passes; layouts LRay does not write and claims the
// file's bytes cannot hold are refused with a reason.
#include "shading/exr_header.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace lray {
namespace {

namespace fs = std::filesystem;

const ExrHeaderLimits kLimits{uint64_t{1} << 28, 64};

class ExrHeader : public ::testing::Test {
protected:
  void SetUp() override {
    path_ = (fs::temp_directory_path() / ("lray_exr_header_" + std::to_string(getpid()) + ".exr"))
                .string();
  }
  void TearDown() override { fs::remove(path_); }

  void write(const char *compression, int channels = 3, bool tiled = false) {
    OIIO::ImageSpec spec(32, 20, channels, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", compression);
    if (tiled) spec.tile_width = spec.tile_height = 16;
    auto out = OIIO::ImageOutput::create(path_);
    ASSERT_TRUE(out && out->open(path_, spec));
    std::vector<float> pixels(size_t(32) * 20 * channels, 0.25f);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
  }
  std::string bytes() const {
    std::ifstream in(path_, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  void replace(const std::string &b) { std::ofstream(path_, std::ios::binary) << b; }

  std::string path_;
};

TEST_F(ExrHeader, WhatLrayWritesPasses) {
  for (const char *c : {"zip", "none", "rle", "zips", "piz"}) {
    write(c);
    EXPECT_EQ(checkExrHeader(path_, kLimits), "") << c;
  }
}

TEST_F(ExrHeader, OtherLayoutsAreRefused) {
  write("b44");
  EXPECT_EQ(checkExrHeader(path_, kLimits), "not losslessly compressed (as LRay writes them)");
  write("zip", 3, true);
  EXPECT_EQ(checkExrHeader(path_, kLimits), "not a single-part scanline EXR (as LRay writes them)");
  write("zip", 16);
  EXPECT_EQ(checkExrHeader(path_, {uint64_t{1} << 28, 12}), "16 channels, more than LRay reads");
  replace("not an exr at all");
  EXPECT_EQ(checkExrHeader(path_, kLimits), "not an EXR file");
  EXPECT_EQ(checkExrHeader(path_ + ".missing", kLimits), "cannot open it");
}

TEST_F(ExrHeader, ClaimsTheFileCannotHoldAreRefused) {
  write("zip");
  const std::string good = bytes();
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = good.find(key) + key.size() + 4;
  auto withWindow = [&](int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    std::string b = good;
    const int32_t box[4] = {x0, y0, x1, y1};
    std::memcpy(&b[at], box, sizeof box);
    replace(b);
    return checkExrHeader(path_, kLimits);
  };
  EXPECT_EQ(withWindow(0, 0, 31, 19), "");
  EXPECT_EQ(withWindow(0, 0, 4095, 4095), "its header claims 4096 x 4096 pixels, more than its " +
                                              std::to_string(good.size()) + " bytes can hold");
  EXPECT_EQ(withWindow(-2147483647 - 1, 0, 2147483647, 0),
            "its header claims a window of 4294967296 x 1 pixels, more than LRay reads");
  EXPECT_EQ(withWindow(0, 0, -5, 3),
            "its header claims a window of -4 x 4 pixels, more than LRay reads");
  // Cut anywhere in the header: refused, never read past the end.
  for (size_t n = 8; n < good.find(key) + 40; n += 7) {
    replace(good.substr(0, n));
    EXPECT_NE(checkExrHeader(path_, kLimits), "") << n;
  }
}

} // namespace
} // namespace lray
