// Tests for src/render/image_writer: quantisation, formats, atomic writes.
#include "render/image_writer.h"
#include "shading/oiio_library.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>
#include <set>

#include <filesystem>

namespace lray {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string &name) {
  fs::path dir =
      fs::temp_directory_path() / ("lray_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(ImageWriter, QuantizeClampsAndRounds) {
  EXPECT_EQ(quantize8(-1.f, false), 0);
  EXPECT_EQ(quantize8(2.f, false), 255);
  EXPECT_EQ(quantize8(0.5f, false), 128); // 127.5 rounds up
  EXPECT_EQ(quantize8(0.4f / 255.f, false), 0);
  EXPECT_EQ(quantize8(0.6f / 255.f, false), 1);
  EXPECT_EQ(quantize8(std::nanf(""), false), 0);
}

TEST(ImageWriter, QuantizeSrgbEncodes) {
  EXPECT_EQ(quantize8(0.f, true), 0);
  EXPECT_EQ(quantize8(1.f, true), 255);
  EXPECT_EQ(quantize8(0.5f, true), 188); // sRGB(0.5) = 0.7354
  EXPECT_EQ(quantize8(0.002f, true), 7); // linear segment: 12.92 * 0.002 * 255 = 6.6
}

TEST(ImageWriter, QuantizeRoundsAsLroundDoes) {
  // The rounding without std::lround against the formula with it, over a
  // stride of all floats in [0, 1] and over every float within 4096 steps
  // of each point where the 8-bit value changes (k + 0.5 after the scale,
  // the sRGB curve undone for the encoded values).
  auto reference = [](float value, bool srgb) {
    float v = std::isnan(value) ? 0.f : std::clamp(value, 0.f, 1.f);
    if (srgb) v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
    return static_cast<uint8_t>(std::lround(std::clamp(v, 0.f, 1.f) * 255.f));
  };
  size_t checked = 0;
  auto check = [&](float v) {
    for (bool srgb : {false, true}) {
      ASSERT_EQ(quantize8(v, srgb), reference(v, srgb)) << v << (srgb ? " srgb" : "");
      ++checked;
    }
  };
  for (uint32_t bits = 0; bits <= 0x3f800000u; bits += 997) {
    float v;
    std::memcpy(&v, &bits, sizeof v);
    check(v);
  }
  for (int k = 0; k < 255; ++k) {
    const double encoded = (k + 0.5) / 255;
    const double linear = encoded <= 0.04045 ? encoded / 12.92
                                             : std::pow((encoded + 0.055) / 1.055, 2.4);
    for (double centre : {encoded, linear}) {
      float v = static_cast<float>(centre);
      for (int step = 0; step < 4096; ++step) v = std::nextafter(v, 0.f);
      for (int step = 0; step < 8192; ++step, v = std::nextafter(v, 2.f)) check(v);
    }
  }
  EXPECT_GT(checked, 5000000u);
}

TEST(ImageWriter, QuantizeFilmIsQuantizeValueByValue) {
  // The frame's loop (its own inline copy for linear values) against
  // quantize8, on values around every 8-bit step, out of range and NaN.
  const float specials[] = {-0.f, 0.f, -1.f, 1.f, 2.f, std::nanf(""), -std::nanf(""),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::denorm_min(), 0x1p-149f * 3};
  std::vector<float> values(std::begin(specials), std::end(specials));
  for (int k = 0; k <= 255; ++k) {
    float v = (k + 0.5f) / 255.f;
    for (int step = 0; step < 8; ++step) v = std::nextafter(v, 0.f);
    for (int step = 0; step < 16; ++step, v = std::nextafter(v, 2.f)) values.push_back(v);
  }
  values.resize((values.size() + 2) / 3 * 3, 0.25f);
  Film film(static_cast<int>(values.size() / 3), 1);
  for (int x = 0; x < film.width(); ++x)
    film.set(x, 0, {values[3 * x], values[3 * x + 1], values[3 * x + 2]});
  for (bool srgb : {false, true}) {
    const std::vector<uint8_t> bytes = quantizeFilm(film, srgb);
    ASSERT_EQ(bytes.size(), film.data().size());
    for (size_t i = 0; i < bytes.size(); ++i)
      ASSERT_EQ(bytes[i], quantize8(film.data()[i], srgb)) << film.data()[i] << " " << srgb;
  }
}

Film testFilm() {
  Film film(3, 2);
  film.set(0, 0, {1, 0, 0});
  film.set(1, 0, {0, 1, 0});
  film.set(2, 0, {0, 0, 1});
  film.set(0, 1, {0.5, 0.25, 2.0});
  return film;
}

TEST(ImageWriter, PngRoundTripKeepsPixelsAndOrientation) {
  fs::path dir = freshDir("png");
  std::string path = (dir / "a.png").string();
  writeImage(testFilm(), path, ImageFormat::Png, false);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 3);
  EXPECT_EQ(in->spec().height, 2);
  std::vector<uint8_t> px(3 * 2 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
  EXPECT_EQ(px[0], 255); // top-left red
  EXPECT_EQ(px[4], 255); // (1,0) green
  EXPECT_EQ(px[8], 255); // (2,0) blue
  EXPECT_EQ(px[9], 128);
  EXPECT_EQ(px[10], 64);
  EXPECT_EQ(px[11], 255); // clamped
  // Nothing but the final file is left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(ImageWriter, ExrKeepsUnclampedFloats) {
  fs::path dir = freshDir("exr");
  std::string path = (dir / "a.exr").string();
  writeImage(testFilm(), path, ImageFormat::Exr, false);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  std::vector<float> px(3 * 2 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  EXPECT_FLOAT_EQ(px[11], 2.0f);
  EXPECT_FLOAT_EQ(px[10], 0.25f);
  fs::remove_all(dir);
}

TEST(ImageWriter, ExrCarriesTheErrorEstimateSampleCountVarianceAndAovLayers) {
  fs::path dir = freshDir("exr_layers");
  Film film = testFilm();
  film.setError(1, 0, 0.125f);
  film.setSampleCount(1, 0, 64);
  film.setVariance(1, 0, {0.5, 0.25, 0.0625});
  film.enableAovs();
  film.aov(1, 0) = {3.5f, {0, 1, 0}, {0.9f, 0.5f, 0.1f}};
  std::string path = (dir / "a.exr").string();
  writeImage(film, path, ImageFormat::Exr, false);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const std::vector<std::string> expected{
      "R",   "G",   "B",   "Error",    "SampleCount", "Variance.R", "Variance.G", "Variance.B",
      "Z",   "N.X", "N.Y", "N.Z",      "Albedo.R",    "Albedo.G",   "Albedo.B"};
  // OpenEXR stores channels sorted by name; OpenImageIO gives them back in
  // its own order, so compare as sets and read each by name.
  const auto &names = in->spec().channelnames;
  ASSERT_EQ(std::set<std::string>(names.begin(), names.end()),
            std::set<std::string>(expected.begin(), expected.end()));
  const int nc = in->spec().nchannels;
  std::vector<float> px(static_cast<size_t>(nc) * 2 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, px.data()));
  auto at = [&](int x, int y, const std::string &name) {
    const int c = in->spec().channelindex(name);
    return px[(static_cast<size_t>(y) * 3 + x) * nc + c];
  };
  EXPECT_FLOAT_EQ(at(1, 0, "Error"), 0.125f);
  EXPECT_FLOAT_EQ(at(1, 0, "SampleCount"), 64);
  EXPECT_FLOAT_EQ(at(1, 0, "Variance.G"), 0.25f);
  EXPECT_FLOAT_EQ(at(1, 0, "Z"), 3.5f);
  EXPECT_FLOAT_EQ(at(1, 0, "N.Y"), 1);
  EXPECT_FLOAT_EQ(at(1, 0, "Albedo.R"), 0.9f);
  EXPECT_FLOAT_EQ(at(0, 1, "B"), 2.0f);
  EXPECT_FLOAT_EQ(at(0, 1, "G"), 0.25f);
  fs::remove_all(dir);
}

TEST(ImageWriter, TgaIsWritten) {
  fs::path dir = freshDir("tga");
  std::string path = (dir / "a.tga").string();
  writeImage(testFilm(), path, ImageFormat::Tga, false);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(std::string(in->format_name()), "targa");
  fs::remove_all(dir);
}

TEST(ImageWriter, FailureLeavesNoFile) {
  fs::path dir = freshDir("fail");
  std::string path = (dir / "missing_folder" / "a.png").string();
  EXPECT_THROW(writeImage(testFilm(), path, ImageFormat::Png, false), std::runtime_error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  fs::remove_all(dir);
}

TEST(ImageWriter, ReplacesAnExistingFileWhole) {
  fs::path dir = freshDir("replace");
  std::string path = (dir / "a.png").string();
  Film big(64, 64);
  writeImage(big, path, ImageFormat::Png, false);
  writeImage(testFilm(), path, ImageFormat::Png, false);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 3);
  fs::remove_all(dir);
}

TEST(ImageLibrary, PngAndTgaOutputLeaveOpenImageIOUnloaded) {
  // OpenImageIO's module is loaded for EXR (and image textures) only: a
  // PNG or TGA render does not pay for its libraries (this suite runs in a
  // process of its own).
  fs::path dir = freshDir("lazy");
  writeImage(testFilm(), (dir / "a.png").string(), ImageFormat::Png, false);
  writeImage(testFilm(), (dir / "a.tga").string(), ImageFormat::Tga, true);
  EXPECT_FALSE(oiioLibraryLoaded());
  writeImage(testFilm(), (dir / "a.exr").string(), ImageFormat::Exr, false);
  EXPECT_TRUE(oiioLibraryLoaded());
  fs::remove_all(dir);
}

TEST(ImageLibrary, SrgbPngSaysSoAndTgaKeepsPixels) {
  fs::path dir = freshDir("tags");
  std::string png = (dir / "s.png").string(), tga = (dir / "t.tga").string();
  writeImage(testFilm(), png, ImageFormat::Png, true);
  writeImage(testFilm(), tga, ImageFormat::Tga, false);
  auto in = OIIO::ImageInput::open(png);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
  auto t = OIIO::ImageInput::open(tga);
  ASSERT_TRUE(t);
  std::vector<uint8_t> px(3 * 2 * 3);
  ASSERT_TRUE(t->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
  EXPECT_EQ(px[0], 255); // top-left red: rows in order
  EXPECT_EQ(px[9], 128);
  EXPECT_EQ(px[10], 64);
  fs::remove_all(dir);
}

} // namespace
} // namespace lray
