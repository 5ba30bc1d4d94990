// Tests for src/shading/image_cache and texture_image: decoding through
// OpenImageIO (images written by the test), sRGB handling and the wrapped
// bilinear lookup.
#include "shading/image_cache.h"

#include "shading/oiio_library.h"
#include "shading/texture_file.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <unistd.h>

namespace lray {
namespace {

namespace fs = std::filesystem;

/// A private temp folder per test, removed afterwards.
class ImageCacheTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lray_image_cache_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Writes a 2x2 8-bit RGB PNG: top row (10, 20, 30) (40, 50, 60), bottom
  /// row (70, 80, 90) (255, 0, 128).
  std::string writePng() {
    std::string path = (dir_ / "tiny.png").string();
    const uint8_t px[] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 255, 0, 128};
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
    return path;
  }

  fs::path dir_;
};

Color c8(int r, int g, int b) { return Color(r / 255.0, g / 255.0, b / 255.0); }

void expectColor(const Color &a, const Color &b, double tol = 1e-6) {
  EXPECT_NEAR(a.r, b.r, tol);
  EXPECT_NEAR(a.g, b.g, tol);
  EXPECT_NEAR(a.b, b.b, tol);
}

TEST_F(ImageCacheTest, ReadsEightBitAsStoredWithBottomRowAtTZero) {
  TextureImage img = ImageCache::readImage(writePng(), false);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 2);
  // Texel centres: s = 0.25 / 0.75, t = 0.25 is the bottom row.
  expectColor(img.lookup(0.25, 0.25), c8(70, 80, 90));
  expectColor(img.lookup(0.75, 0.25), c8(255, 0, 128));
  expectColor(img.lookup(0.25, 0.75), c8(10, 20, 30));
  expectColor(img.lookup(0.75, 0.75), c8(40, 50, 60));
}

TEST_F(ImageCacheTest, BilinearBetweenCentresAndWrapped) {
  TextureImage img = ImageCache::readImage(writePng(), false);
  Color bl = c8(70, 80, 90), br = c8(255, 0, 128), tl = c8(10, 20, 30), tr = c8(40, 50, 60);
  expectColor(img.lookup(0.5, 0.25), (bl + br) * 0.5);
  expectColor(img.lookup(0.5, 0.5), (bl + br + tl + tr) * 0.25);
  // s = 0 lies halfway between the last column (wrapped) and the first.
  expectColor(img.lookup(0.0, 0.25), (bl + br) * 0.5);
  expectColor(img.lookup(0.375, 0.25), bl * 0.75 + br * 0.25);
  // Repeat: whole-number shifts, including negative, change nothing.
  expectColor(img.lookup(1.25, 0.25), bl);
  expectColor(img.lookup(-0.75, -1.75), bl);
  expectColor(img.lookup(-0.25, 0.75), tr);
  // t = 1 wraps to t = 0: halfway between bottom and top rows.
  expectColor(img.lookup(0.25, 1.0), (bl + tl) * 0.5);
  EXPECT_TRUE(isFinite(img.lookup(std::nan(""), 1e300)));
}

TEST_F(ImageCacheTest, LinearWorkflowDecodesSrgb) {
  TextureImage img = ImageCache::readImage(writePng(), true);
  auto srgb = [](double c) {
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  Color got = img.lookup(0.75, 0.25);
  EXPECT_NEAR(got.r, 1.0, 1e-6);
  EXPECT_NEAR(got.g, 0.0, 1e-6);
  EXPECT_NEAR(got.b, srgb(128 / 255.0), 1e-5);
  EXPECT_NEAR(img.lookup(0.25, 0.75).r, srgb(10 / 255.0), 1e-6);
}

TEST_F(ImageCacheTest, FloatImagesUsedAsIs) {
  std::string path = (dir_ / "tiny.exr").string();
  const float px[] = {2.5f, 0.25f, 0.125f};
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px));
  out->close();
  TextureImage img = ImageCache::readImage(path, true);
  expectColor(img.lookup(0.3, 0.9), {2.5, 0.25, 0.125});
}

TEST_F(ImageCacheTest, RgbaTgaDropsAlphaAndGreyIsReplicated) {
  std::string tga = (dir_ / "rgba.tga").string();
  {
    const uint8_t px[] = {200, 100, 50, 7};
    auto out = OIIO::ImageOutput::create(tga);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1); // write the colour bytes as given
    ASSERT_TRUE(out->open(tga, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
  }
  // Colours as stored, not premultiplied by the alpha of 7.
  Color c = ImageCache::readImage(tga, false).lookup(0.5, 0.5);
  expectColor(c, c8(200, 100, 50));

  std::string grey = (dir_ / "grey.png").string();
  {
    const uint8_t px[] = {51};
    auto out = OIIO::ImageOutput::create(grey);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(grey, OIIO::ImageSpec(1, 1, 1, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
  }
  expectColor(ImageCache::readImage(grey, false).lookup(0.1, 0.9), {0.2, 0.2, 0.2});
}

TEST_F(ImageCacheTest, StbDecodesPngAndTgaToTheSameTexelsAsOpenImageIo) {
  // Every channel count, odd sizes, both workflows: the two decoders must
  // agree texel for texel, or a scene would change with the format's path.
  int made = 0;
  for (int nch : {1, 2, 3, 4}) {
    for (const char *ext : {"png", "tga"}) {
      const int w = 7, h = 5;
      std::vector<uint8_t> px(static_cast<size_t>(w) * h * nch);
      for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<uint8_t>((i * 37 + 11) % 256);
      const std::string path = (dir_ / ("t" + std::to_string(nch) + "." + ext)).string();
      auto out = OIIO::ImageOutput::create(path);
      ASSERT_TRUE(out);
      OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::UINT8);
      if (nch == 2 || nch == 4) spec.alpha_channel = nch - 1;
      ASSERT_TRUE(out->open(path, spec));
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
      out->close();
      for (bool linear : {false, true}) {
        std::optional<TextureImage> fast = decodeEightBitTexture(path, linear, {});
        // OpenImageIO writes grey + alpha TGA as 16-bit pixels, which stb
        // is not given (texture_file.h): those stay with OpenImageIO.
        if (!fast) {
          EXPECT_TRUE(std::string(ext) == "tga" && nch == 2) << path;
          continue;
        }
        ++made;
        const TextureImage slow = oiioLibrary().readImage(path, linear, {}, nullptr);
        EXPECT_EQ(fast->width, slow.width);
        EXPECT_EQ(fast->height, slow.height);
        EXPECT_EQ(fast->rgb, slow.rgb) << path << (linear ? " linear" : "");
      }
    }
  }
  EXPECT_GE(made, 12);
  // A 16-bit PNG is left to OpenImageIO.
  const std::string deep = (dir_ / "deep.png").string();
  auto out = OIIO::ImageOutput::create(deep);
  OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT16);
  ASSERT_TRUE(out->open(deep, spec));
  const uint16_t px16[12] = {};
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, px16));
  out->close();
  EXPECT_FALSE(decodeEightBitTexture(deep, false, {}));
}

TEST_F(ImageCacheTest, LoadsEachPathOnce) {
  Scene scene;
  std::string path = writePng();
  scene.images.push_back({path, {}});
  scene.images.push_back({path, {}});
  ImageCache cache(false);
  cache.load(scene);
  EXPECT_EQ(cache.size(), 1u);
  const TextureImage *first = cache.find(path);
  ASSERT_NE(first, nullptr);
  cache.load(scene); // next frame: nothing reloaded, pointers stay valid
  EXPECT_EQ(cache.find(path), first);
  EXPECT_EQ(cache.find(path + ".other"), nullptr);
  EXPECT_GE(cache.memoryBytes(), 12 * sizeof(float));
}

TEST_F(ImageCacheTest, MissingImageIsASceneErrorNamingPathAndLine) {
  Scene scene;
  std::string path = (dir_ / "nope.png").string();
  scene.images.push_back({path, {"scene.lua", 12}});
  ImageCache cache(false);
  try {
    cache.load(scene);
    FAIL() << "expected SceneError";
  } catch (const SceneError &e) {
    std::string what = e.what();
    EXPECT_NE(what.find("scene.lua:12"), std::string::npos) << what;
    EXPECT_NE(what.find(path), std::string::npos) << what;
  }
}

TEST_F(ImageCacheTest, DecodingIsChargedWithEveryChannelBeforeItIsAllocated) {
  // A 16-channel float EXR decodes as 16 floats a texel, then keeps 3.
  const int w = 64, h = 32;
  std::vector<std::string> channels;
  for (int c = 0; c < 16; ++c) channels.push_back("C" + std::to_string(c));
  const std::vector<float> pixels(size_t{w} * h * 16, 0.5f);
  const std::string path = (dir_ / "deep.exr").string();
  ASSERT_EQ(oiioLibrary().writeFloat(path, w, h, channels, pixels.data()), "");
  const uint64_t decoded = uint64_t{w} * h * 16 * 4, kept = uint64_t{w} * h * 3 * 4;
  MemoryBudget tight(decoded + kept - 1, 0);
  try {
    ImageCache::readImage(path, false, {"s.lua", 7}, &tight);
    ADD_FAILURE() << "decoded past the budget";
  } catch (const SceneError &e) {
    EXPECT_NE(std::string(e.what()).find("s.lua:7: ImagePigment2D: image '" + path +
                                         "': the frame would need more than the render memory "
                                         "budget of"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(tight.used(), 0u);
  MemoryBudget enough(decoded + kept, 0);
  ImageCache::readImage(path, false, {}, &enough);
  EXPECT_EQ(enough.used(), kept) << "the decoder's buffer is given back, the texels kept";
  // The 8-bit decoder charges the same way: 3 bytes and 3 floats a texel.
  MemoryBudget small(10, 0);
  EXPECT_THROW(ImageCache::readImage(writePng(), false, {}, &small), SceneError);
}

TEST_F(ImageCacheTest, UnreadableImageIsASceneError) {
  std::string path = (dir_ / "garbage.png").string();
  FILE *f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fputs("this is not a png", f);
  std::fclose(f);
  EXPECT_THROW(ImageCache::readImage(path, false), SceneError);
}

/// CRC-32 of a PNG chunk's type and data (ISO 3309, as PNG defines it).
uint32_t pngCrc(const std::string &bytes) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

std::string bigEndian(uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

std::string pngChunk(const std::string &type, const std::string &data) {
  return bigEndian(static_cast<uint32_t>(data.size())) + type + data +
         bigEndian(pngCrc(type + data));
}

TEST_F(ImageCacheTest, AHeaderClaimingAHugeImageIsRefusedBeforeAllocating) {
  // A 100-byte file whose header says 100000 x 100000 (120 GB as float RGB).
  std::string ihdr = bigEndian(100000) + bigEndian(100000) + std::string("\x08\x02\x00\x00\x00", 5);
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) +
                    pngChunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
                    pngChunk("IEND", "");
  fs::path path = dir_ / "huge.png";
  std::ofstream(path, std::ios::binary) << png;
  try {
    ImageCache::readImage(path.string(), false, {"s.lua", 3});
    FAIL() << "expected a SceneError";
  } catch (const SceneError &e) {
    EXPECT_EQ(std::string(e.what()), "s.lua:3: ImagePigment2D: image '" + path.string() +
                                         "' is 100000 x 100000 texels, more than the limit of "
                                         "268435456");
  }
}

} // namespace
} // namespace lray
