// Tests for adaptive sampling and spread light sampling (render/
// tile_renderer_impl.h, sample_buffer.h, pixel_error.h, owen_sobol.h):
// determinism across thread counts, the stopping rule, error against a
// converged reference falling with the threshold, the unbiasedness of
// spreading a light's cells over a pixel's samples, and time limits.
#include "render/backends.h"
#include "math/owen_sobol.h"
#include "render/pixel_error.h"
#include "render/renderer.h"
#include "render/render_films.h"
#include "render/sample_buffer.h"
#include "shading/image_cache.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <string>

namespace lray {
namespace {

/// A white floor, a red sphere and a cube between them and a 4 x 4 jittered
/// area light: hard edges, a penumbra and flat regions in 48 x 32 pixels.
Scene penumbraScene() {
  Scene s;
  auto texture = [&](const Color &c, double specular) {
    Pigment p;
    p.pattern = ColorPigment{c};
    s.pigments.push_back(p);
    Finish f;
    f.specular = specular;
    f.exponent = 20;
    s.textures.push_back({f, static_cast<uint32_t>(s.pigments.size() - 1)});
    return static_cast<uint32_t>(s.textures.size() - 1);
  };
  auto add = [&](Shape shape, const Transform &t, uint32_t tex) {
    Entity e;
    e.shape = shape;
    e.worldFromObject = t;
    e.texture = tex;
    s.entities.push_back(e);
  };
  add(Plane{}, Transform(), texture({0.9, 0.9, 0.9}, 0));
  add(Sphere{}, Transform::translate({-0.8, 1, 0}), texture({0.9, 0.2, 0.2}, 0.5));
  add(Cube{}, Transform::translate({1.2, 0.6, -0.5}) * Transform::scale(1.2, 1.2, 1.2),
      texture({0.2, 0.3, 0.9}, 0));
  Light light;
  light.rows = light.cols = 4;
  light.area = true;
  light.worldFromLight = Transform::translate({-3, 5, -2}) * Transform::scale(2, 1, 2);
  s.lights.push_back(light);
  s.background = {0.05, 0.05, 0.1};
  s.camera.fov = 50;
  s.camera.aspect = 1.5;
  s.camera.worldFromCamera = Transform::lookAt({0, 3, -6}, {0, 0.7, 0}, {0, 1, 0});
  return s;
}

constexpr int kWidth = 48, kHeight = 32;

FrameSettings fixedSettings(int n, LightSampling light = LightSampling::All, int frame = 0) {
  FrameSettings fs;
  fs.width = kWidth;
  fs.height = kHeight;
  fs.samples = n;
  fs.lightSampling = light;
  fs.frameIndex = frame;
  return fs;
}

FrameSettings adaptiveSettings(double threshold, int minSamples, int maxSamples,
                               LightSampling light = LightSampling::Spread) {
  FrameSettings fs = fixedSettings(1, light);
  fs.adaptive = true;
  fs.adaptiveSettings.noiseThreshold = threshold;
  fs.adaptiveSettings.minSamples = minSamples;
  fs.adaptiveSettings.maxSamples = maxSamples;
  return fs;
}

using test::render;
using test::rmse;

class AdaptiveSampling : public ::testing::TestWithParam<BackendKind> {
protected:
  Scene scene = penumbraScene();
  std::unique_ptr<Accelerator> accel = makeAccelerator(GetParam(), scene);
};

TEST_P(AdaptiveSampling, SameBytesSamplesAndEstimatesForAnyThreadCount) {
  for (int minSamples : {4, 1}) { // 1: the centre-first pass
    const FrameSettings fs = adaptiveSettings(0.02, minSamples, 64);
    const Film one = test::renderOnThreads(scene, *accel, fs, 1);
    const Film many = test::renderOnThreads(scene, *accel, fs, 4);
    EXPECT_EQ(one.data(), many.data()) << minSamples;
    EXPECT_EQ(one.estimateData(), many.estimateData()) << minSamples;
    EXPECT_EQ(one.report.samples, many.report.samples) << minSamples;
    EXPECT_GT(one.report.passes, 1) << minSamples;
  }
}

TEST_P(AdaptiveSampling, EveryPixelStopsConvergedWithItsNeighboursOrAtTheMaximum) {
  const double threshold = 0.03;
  const int minSamples = 8, maxSamples = 128;
  Film film = render(scene, *accel, adaptiveSettings(threshold, minSamples, maxSamples));
  uint32_t fewest = UINT32_MAX, most = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const uint32_t n = film.sampleCount(x, y);
      fewest = std::min(fewest, n);
      most = std::max(most, n);
      if (n >= static_cast<uint32_t>(maxSamples)) continue;
      // Stopped early: it and all its neighbours below the threshold (or
      // at the maximum).
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= kWidth || ny >= kHeight) continue;
          if (film.sampleCount(nx, ny) >= static_cast<uint32_t>(maxSamples)) continue;
          EXPECT_LT(film.error(nx, ny), threshold)
              << nx << "," << ny << " next to " << x << "," << y;
        }
    }
  }
  // The flat floor stops after the first pass; edges and the penumbra do not.
  EXPECT_EQ(fewest, static_cast<uint32_t>(minSamples));
  EXPECT_GT(most, static_cast<uint32_t>(2 * minSamples));
  EXPECT_LT(film.report.samples, static_cast<uint64_t>(maxSamples) * kWidth * kHeight / 2)
      << "adaptive sampling should spend well under the maximum on this scene";
}

TEST_P(AdaptiveSampling, ErrorAgainstAConvergedReferenceFallsWithTheThreshold) {
  const Film reference = render(scene, *accel, fixedSettings(24));
  double lastError = 1e9;
  uint64_t lastSamples = 0;
  for (double threshold : {0.2, 0.05, 0.012, 0.003}) {
    const Film film = render(scene, *accel, adaptiveSettings(threshold, 4, 512));
    const double error = rmse(film, reference);
    EXPECT_GT(film.report.samples, lastSamples) << threshold;
    EXPECT_LT(error, lastError) << threshold;
    lastError = error;
    lastSamples = film.report.samples;
  }
  // No error floor: the smallest threshold is within a few times the
  // reference's own noise of it.
  EXPECT_LT(lastError, 0.01);
}

// --min-samples 1: one sample through each pixel centre; a pixel stops
// there unless it differs from a neighbour or most of its neighbours do,
// else it drops the centre sample and takes Sobol passes from 4.
TEST_P(AdaptiveSampling, CentreFirstStopsFlatPixelsAtTheirCentreSample) {
  const double threshold = 0.03;
  const Film film = render(scene, *accel, adaptiveSettings(threshold, 1, 128));
  const Film centres = render(scene, *accel, fixedSettings(1, LightSampling::All));
  int atCentre = 0, besideAnEdge = 0;
  SampleBuffer contrast(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) contrast.setCentre(contrast.index(x, y), centres.get(x, y));
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const uint32_t n = film.sampleCount(x, y);
      // One sample, or a restart: never the centre plus Sobol samples.
      ASSERT_TRUE(n == 1 || n >= 4) << x << "," << y << ": " << n;
      if (n != 1) continue;
      ++atCentre;
      // Exactly the 1 x 1 render's pixel (every light cell), ...
      ASSERT_EQ(film.get(x, y), centres.get(x, y)) << x << "," << y;
      // ... and it did not differ from its neighbours by the threshold,
      // nor did most of them from theirs.
      EXPECT_LT(contrast.centreContrast(contrast.index(x, y)), threshold) << x << "," << y;
      int neighbours = 0, edges = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((!dx && !dy) || nx < 0 || ny < 0 || nx >= kWidth || ny >= kHeight) continue;
          ++neighbours;
          edges += contrast.centreContrast(contrast.index(nx, ny)) >= threshold;
        }
      EXPECT_LE(2 * edges, neighbours) << x << "," << y;
      besideAnEdge += edges > 0;
    }
  }
  // The flat floor and background stop at their centres (a fifth of this
  // small frame); edges and the penumbra do not. Fewer samples than a
  // first pass of 4 at the same threshold.
  EXPECT_GT(atCentre, kWidth * kHeight / 5);
  EXPECT_LT(atCentre, kWidth * kHeight);
  // Pixels along an edge take samples; those beside them, whose centres
  // match all their neighbours', do not (SampleBuffer::setActiveAround).
  EXPECT_GT(besideAnEdge, 0);
  EXPECT_LT(film.report.samples,
            render(scene, *accel, adaptiveSettings(threshold, 4, 128)).report.samples);
}

TEST_P(AdaptiveSampling, CentreFirstConvergesWithTheThreshold) {
  const Film reference = render(scene, *accel, fixedSettings(24));
  double lastError = 1e9;
  for (double threshold : {0.2, 0.05, 0.012, 0.003}) {
    const double error =
        rmse(render(scene, *accel, adaptiveSettings(threshold, 1, 512)), reference);
    EXPECT_LT(error, lastError) << threshold;
    lastError = error;
  }
  EXPECT_LT(lastError, 0.01);
  // A zero threshold: every pixel restarts and takes the maximum.
  const Film all = render(scene, *accel, adaptiveSettings(0, 1, 24));
  EXPECT_EQ(all.report.samples, 24u * kWidth * kHeight);
  EXPECT_EQ(all.report.passes, 6); // the centres, then 4, 8, 12, 18, 24
}

TEST_P(AdaptiveSampling, ZeroThresholdTakesTheMaximumEverywhere) {
  const Film film = render(scene, *accel, adaptiveSettings(0, 4, 24));
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) ASSERT_EQ(film.sampleCount(x, y), 24u);
  EXPECT_EQ(film.report.samples, 24u * kWidth * kHeight);
  // 4, 8, 12, 18, 24.
  EXPECT_EQ(film.report.passes, 5);
}

TEST_P(AdaptiveSampling, SpreadShadesEachCellOncePerPixelAcrossItsSamples) {
  // 4 x 4 samples and 16 cells: spread casts one shadow ray per lit sample,
  // all casts sixteen.
  RayCounts all, spread;
  render(scene, *accel, fixedSettings(4, LightSampling::All), &all);
  render(scene, *accel, fixedSettings(4, LightSampling::Spread), &spread);
  EXPECT_EQ(all.camera, spread.camera);
  EXPECT_GT(spread.shadow, 0u);
  EXPECT_NEAR(static_cast<double>(all.shadow) / static_cast<double>(spread.shadow), 16, 0.5);
}

/// Mean over many random streams (frame indices) of a block of pixels.
struct BlockMeans {
  static constexpr int kBlock = 8;
  std::vector<double> sum, sumSquares;
  int runs = 0;
  BlockMeans() : sum((kWidth / kBlock) * (kHeight / kBlock), 0), sumSquares(sum.size(), 0) {}
  void add(const Film &film) {
    std::vector<double> block(sum.size(), 0);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const Color c = film.get(x, y);
        block[(y / kBlock) * (kWidth / kBlock) + x / kBlock] += c.r + c.g + c.b;
      }
    for (size_t i = 0; i < block.size(); ++i) {
      sum[i] += block[i];
      sumSquares[i] += block[i] * block[i];
    }
    ++runs;
  }
  double mean(size_t i) const { return sum[i] / runs; }
  double standardError(size_t i) const {
    const double m = mean(i);
    return std::sqrt(std::max(0.0, sumSquares[i] / runs - m * m) / (runs - 1));
  }
};

TEST_P(AdaptiveSampling, SpreadHasTheSameExpectedValueAsAllCells) {
  // Each run's random stream is keyed by its frame index. Per 8 x 8 block,
  // the means of 48 runs of each mode agree within 4.5 standard errors;
  // the penumbra blocks carry the spread's extra variance.
  constexpr int kRuns = 48;
  BlockMeans all, spread, spreadAdaptive;
  for (int run = 0; run < kRuns; ++run) {
    all.add(render(scene, *accel, fixedSettings(2, LightSampling::All, run)));
    spread.add(render(scene, *accel, fixedSettings(2, LightSampling::Spread, run)));
    FrameSettings fs = adaptiveSettings(0, 8, 8);
    fs.frameIndex = run;
    spreadAdaptive.add(render(scene, *accel, fs));
  }
  int differing = 0;
  for (size_t i = 0; i < all.sum.size(); ++i) {
    for (const BlockMeans *other : {&spread, &spreadAdaptive}) {
      const double se = std::hypot(all.standardError(i), other->standardError(i));
      const double gap = std::abs(all.mean(i) - other->mean(i));
      EXPECT_LT(gap, 4.5 * se + 1e-9) << "block " << i;
      if (gap > 1e-9) ++differing;
    }
  }
  // The modes are not the same computation (the test can fail).
  EXPECT_GT(differing, 0);
}

TEST_P(AdaptiveSampling, TimeLimitStopsAfterTheFirstPassWithinAboutOneTile) {
  // Far more work than the limit allows: 65536 samples per pixel.
  FrameSettings fs = adaptiveSettings(0, 2, 65536);
  fs.adaptiveSettings.timeLimit = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  const Film film = render(scene, *accel, fs);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(film.report.timeLimitHit);
  EXPECT_GE(film.report.passes, 2);
  // Generous: a tile's work is milliseconds; only the machine's load matters.
  EXPECT_LT(seconds, 0.2 + 3.0);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) ASSERT_GE(film.sampleCount(x, y), 2u);
}

TEST_P(AdaptiveSampling, CancelStopsAfterTheFirstPass) {
  std::atomic<bool> cancel{true};
  FrameSettings fs = adaptiveSettings(0, 4, 4096);
  fs.cancel = &cancel;
  const Film film = render(scene, *accel, fs);
  EXPECT_TRUE(film.report.cancelled);
  EXPECT_EQ(film.report.passes, 1);
  EXPECT_EQ(film.report.samples, 4u * kWidth * kHeight);
}

TEST_P(AdaptiveSampling, FixedSamplingReportsTheEstimateOfItsSamples) {
  const Film film = render(scene, *accel, fixedSettings(3));
  EXPECT_TRUE(film.report.hasError);
  EXPECT_GT(film.report.maxError, film.report.meanError);
  EXPECT_GT(film.report.meanError, 0);
  EXPECT_EQ(film.report.samples, 9u * kWidth * kHeight);
  const Film one = render(scene, *accel, fixedSettings(1));
  EXPECT_FALSE(one.report.hasError);
}

// The Whitted integrator's samples are stratified: its estimate is the
// samples' spread lowered by (n / 4)^(-1/4), and still above the true
// error; the path tracer's is the spread's alone.
TEST_P(AdaptiveSampling, StratifiedEstimateIsLoweredAndStaysAboveTheTrueError) {
  const Film reference = render(scene, *accel, fixedSettings(24, LightSampling::All, 1));
  for (int n : {4, 8}) {
    const Film film = render(scene, *accel, fixedSettings(n));
    double estimate = 0, actual = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const Color mean = film.get(x, y), spread = film.variance(x, y);
        const double independent = pixelError(mean, spread);
        if (independent == 0) continue;
        EXPECT_NEAR(film.error(x, y) / independent, stratifiedErrorFactor(n * n), 1e-5);
        const Color d = mean - reference.get(x, y);
        actual += (std::abs(d.r) + std::abs(d.g) + std::abs(d.b)) /
                  (1e-4 + std::sqrt(std::max(0.0, mean.r + mean.g + mean.b)));
        estimate += film.error(x, y);
      }
    EXPECT_LT(actual, estimate) << n;
    EXPECT_GT(actual, 0.1 * estimate) << n;
  }
  FrameSettings path = fixedSettings(4);
  path.integrator = IntegratorKind::Path;
  const Film paths = render(scene, *accel, path);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const double independent = pixelError(paths.get(x, y), paths.variance(x, y));
      if (independent > 0) {
        EXPECT_NEAR(paths.error(x, y) / independent, 1, 1e-5);
      }
    }
}

TEST(PixelError, StratifiedSamplesAreCreditedFromFourOn) {
  for (uint32_t n : {0u, 1u, 2u, 3u, 4u}) EXPECT_EQ(stratifiedErrorFactor(n), 1) << n;
  EXPECT_DOUBLE_EQ(stratifiedErrorFactor(16), std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(stratifiedErrorFactor(64), 0.5);
  EXPECT_DOUBLE_EQ(stratifiedErrorFactor(1024), 0.25);
  const Color mean{0.5, 0.2, 0.1}, variance{0.01, 0.02, 0.005};
  EXPECT_EQ(pixelError(mean, variance, 64, SampleSet::Independent), pixelError(mean, variance));
  EXPECT_EQ(pixelError(mean, variance, 64, SampleSet::Stratified),
            pixelError(mean, variance) * 0.5);
}

TEST_P(AdaptiveSampling, AovsGiveDepthNormalAndAlbedoOfTheFirstHit) {
  FrameSettings fs = adaptiveSettings(0.05, 4, 16);
  fs.aovs = true;
  const Film film = render(scene, *accel, fs);
  ASSERT_TRUE(film.hasAovs());
  // The bottom-left corner sees only the white floor: its albedo, a
  // normal turned up and towards the camera (camera space: +y, -z), a
  // depth of a few units.
  const Film::Aov &floor = film.aov(0, kHeight - 1);
  EXPECT_NEAR(floor.albedo[0], 0.9, 1e-6);
  EXPECT_GT(floor.n[1], 0.5);
  EXPECT_LT(floor.n[2], 0);
  EXPECT_NEAR(std::hypot(floor.n[0], floor.n[1], floor.n[2]), 1, 1e-6);
  EXPECT_GT(floor.z, 1);
  EXPECT_LT(floor.z, 10);
  // The top row looks over the horizon: the far floor or nothing; a
  // pixel whose rays all miss has infinite depth and zero albedo.
  int missed = 0;
  for (int x = 0; x < kWidth; ++x) {
    const Film::Aov &a = film.aov(x, 0);
    if (std::isinf(a.z)) {
      ++missed;
      EXPECT_EQ(a.albedo[0], 0);
    } else {
      EXPECT_GT(a.z, floor.z);
    }
  }
  // Without the option, no layers.
  EXPECT_FALSE(render(scene, *accel, adaptiveSettings(0.05, 4, 16)).hasAovs());
  (void)missed;
}

INSTANTIATE_TEST_SUITE_P(Backends, AdaptiveSampling,
                         ::testing::Values(BackendKind::Embree, BackendKind::KdTree),
                         [](const auto &param) { return std::string(backendName(param.param)); });

TEST(PixelError, TheStandardErrorOfTheMeanOverTheSquareRootOfTheBrightness) {
  EXPECT_EQ(pixelError({1, 1, 1}, {0, 0, 0}), 0); // samples that agree
  const Color none = varianceOfMean({1, 1, 1}, {1, 1, 1}, 1); // one sample: no estimate
  EXPECT_EQ(none.r + none.g + none.b, 0);
  // Red samples 0, 2, 0, 2: mean (1, 0, 0), the samples' variance 4/3, the
  // mean's 1/3.
  const Color v = varianceOfMean({4, 0, 0}, {8, 0, 0}, 4);
  EXPECT_NEAR(v.r, 1.0 / 3, 1e-12);
  EXPECT_EQ(v.g, 0);
  EXPECT_NEAR(pixelError({1, 0, 0}, v), std::sqrt(2 / M_PI) * std::sqrt(1.0 / 3) / (1e-4 + 1),
              1e-12);
}

TEST(PixelError, ExpectsWhatTheTwoHalvesEstimateDidAndVariesFarLess) {
  // Pixels of 16 independent samples, each 0 or 1 (a pixel on an edge):
  // the estimate's mean is that of the half-split estimate (|mean of the
  // odd-numbered samples - mean of all| summed over channels, over the
  // square root of the brightness; Dammertz et al. 2010), within the bias
  // of a standard deviation from 16 samples, and it is spread far less
  // around it, so a threshold stops about as much noise, more reliably.
  std::mt19937_64 random(7);
  std::bernoulli_distribution hit(0.3);
  constexpr int kPixels = 20000, kSamples = 16;
  double sum = 0, sumSquares = 0, halfSum = 0, halfSquares = 0;
  for (int p = 0; p < kPixels; ++p) {
    double all = 0, odd = 0, squares = 0;
    for (int k = 0; k < kSamples; ++k) {
      const double v = hit(random) ? 1 : 0;
      all += v;
      squares += v * v;
      if (k & 1) odd += v;
    }
    const Color mean = Color(all, all, all) / kSamples;
    const double e =
        pixelError(mean, varianceOfMean({all, all, all}, {squares, squares, squares}, kSamples));
    const double half = 3 * std::abs(all / kSamples - odd / (kSamples / 2)) /
                        (1e-4 + std::sqrt(3 * all / kSamples));
    sum += e;
    sumSquares += e * e;
    halfSum += half;
    halfSquares += half * half;
  }
  const double mean = sum / kPixels, halfMean = halfSum / kPixels;
  EXPECT_NEAR(mean / halfMean, 1, 0.05);
  const double spread = std::sqrt(sumSquares / kPixels - mean * mean);
  const double halfSpread = std::sqrt(halfSquares / kPixels - halfMean * halfMean);
  EXPECT_LT(spread, 0.5 * halfSpread);
}

TEST(OwenSobol, TheSecondDimensionByTableIsTheXorOfDirectionNumbers) {
  // The definition, bit by bit, against the byte tables, over indices with
  // every byte populated.
  auto byBits = [](uint32_t index) {
    uint32_t v = 1u << 31, x = 0;
    for (; index; index >>= 1, v ^= v >> 1)
      if (index & 1) x ^= v;
    return x;
  };
  uint64_t state = 1;
  for (int k = 0; k < 100000; ++k) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const uint32_t index = k < 1024 ? static_cast<uint32_t>(k) : static_cast<uint32_t>(state >> 32);
    ASSERT_EQ(owen_detail::sobolSecond(index), byBits(index)) << index;
  }
  EXPECT_EQ(owen_detail::sobolSecond(0xffffffffu), byBits(0xffffffffu));
}

TEST(OwenSobol, EveryAlignedBlockOfPowerOfTwoSamplesIsStratified) {
  // (0, m, 2)-net: each elementary interval of area 2^-m holds one point.
  for (uint64_t seed : {1ull, 77ull, 0xdeadbeefcafeull}) {
    for (int m : {2, 4, 6}) {
      const uint32_t count = 1u << m;
      for (uint32_t block : {0u, 1u, 5u}) {
        for (int a = 0; a <= m; ++a) {
          std::set<std::pair<int, int>> cells;
          for (uint32_t i = 0; i < count; ++i) {
            double x, y;
            owenSobol2D(block * count + i, seed, x, y);
            ASSERT_GE(x, 0);
            ASSERT_LT(x, 1);
            cells.insert({static_cast<int>(x * (1 << a)), static_cast<int>(y * (1 << (m - a)))});
          }
          EXPECT_EQ(cells.size(), count) << "seed " << seed << " m " << m << " block " << block;
        }
      }
    }
  }
  // Different seeds, different points.
  double x1, y1, x2, y2;
  owenSobol2D(3, 1, x1, y1);
  owenSobol2D(3, 2, x2, y2);
  EXPECT_NE(x1, x2);
}

TEST(SampleBuffer, AnUnconvergedPixelKeepsItsEightNeighboursActive) {
  SampleBuffer buffer(5, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      // Four samples of 1, but pixel (1,1)'s red ones are 0, 2, 0, 2.
      const bool noisy = x == 1 && y == 1;
      buffer.add(buffer.index(x, y), {4, 4, 4}, {noisy ? 8.0 : 4.0, 4, 4}, 4);
    }
  EXPECT_EQ(buffer.error(buffer.index(0, 0)), 0);
  EXPECT_GT(buffer.error(buffer.index(1, 1)), 0.2);
  EXPECT_EQ(buffer.updateActive(0.01, 100), 9u);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x)
      EXPECT_EQ(buffer.active(buffer.index(x, y)), x <= 2 && y <= 2) << x << "," << y;
  // At the maximum, nothing stays active.
  EXPECT_EQ(buffer.updateActive(0.01, 4), 0u);
}

// After the centre-first pass a pixel joins its neighbours' verdicts only
// where most of them differ: a straight edge keeps the two columns either
// side of it, not a third; a block of centres finer than its surroundings
// takes its middle pixel, whose centre matches all of its neighbours'.
TEST(SampleBuffer, ACentreJoinsItsNeighboursOnlyWhereMostDiffer) {
  auto activeAfterCentres = [](int w, int h, auto colourAt) {
    SampleBuffer buffer(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) buffer.setCentre(buffer.index(x, y), colourAt(x, y));
    buffer.updateActive(0.1, 100);
    std::vector<bool> active;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) active.push_back(buffer.active(x, y));
    return active;
  };
  const Color dark(0.1, 0.1, 0.1), light(0.9, 0.9, 0.9);
  // An edge between columns 2 and 3 of a 6 x 4 frame.
  std::vector<bool> edge =
      activeAfterCentres(6, 4, [&](int x, int) { return x < 3 ? dark : light; });
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      EXPECT_EQ(edge[size_t(y * 6 + x)], x == 2 || x == 3) << x << "," << y;
  // A dark 3 x 3 block inside a light 5 x 5 frame: the block's ring and
  // the frame's border differ; the middle (2, 2) only from nothing.
  std::vector<bool> block = activeAfterCentres(5, 5, [&](int x, int y) {
    return x >= 1 && x <= 3 && y >= 1 && y <= 3 ? dark : light;
  });
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_TRUE(block[size_t(y * 5 + x)]) << x << "," << y;
}

TEST(SampleBuffer, CentreContrastIsTheLargestAgainstANeighbour) {
  // A 3 x 3 frame of centre samples: the middle pixel is grey, its
  // neighbours black but for one white and one mid-grey one.
  SampleBuffer buffer(3, 3);
  buffer.setCentre(buffer.index(1, 1), {0.25, 0.25, 0.25});
  buffer.setCentre(buffer.index(2, 0), {0.3, 0.3, 0.3});
  buffer.setCentre(buffer.index(0, 2), {1, 1, 1});
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      if (!buffer.count(buffer.index(x, y))) buffer.setCentre(buffer.index(x, y), {0, 0, 0});
  // The largest estimate is against the white pixel: 0.5 * 2.25 / sqrt(1.875).
  EXPECT_NEAR(buffer.centreContrast(buffer.index(1, 1)), 0.5 * 2.25 / (1e-4 + std::sqrt(1.875)),
              1e-12);
  // Against a black neighbour: 0.5 * 0.75 / sqrt(0.375).
  EXPECT_NEAR(centrePairContrast({0.25, 0.25, 0.25}, {0, 0, 0}),
              0.5 * 0.75 / (1e-4 + std::sqrt(0.375)), 1e-12);
  // A flat neighbourhood shows no edge.
  SampleBuffer flat(2, 2);
  for (size_t i = 0; i < 4; ++i) flat.setCentre(i, {0.5, 0.5, 0.5});
  EXPECT_EQ(flat.centreContrast(0), 0.0);
  EXPECT_EQ(flat.updateActive(1e-9, 100), 0u);
}

// After the centre-first pass of `colours` (a w x h frame), each pixel
// is active where centreContrast says it or most of its neighbours are
// noisy at `threshold`; cropped: in a region short of the frame's borders.
void expectCentreVerdicts(const std::vector<Color> &colours, int w, int h, double threshold,
                          bool cropped) {
  // A region short of the frame's borders, as for a cropped render.
  SampleBuffer buffer = cropped ? SampleBuffer(w, h, SampleSet::Stratified, 2, 1, w - 3, h - 2)
                                : SampleBuffer(w, h);
  std::vector<uint32_t> active;
  for (size_t i = 0; i < colours.size(); ++i)
    if (buffer.active(i)) {
      active.push_back(static_cast<uint32_t>(i));
      buffer.setCentre(i, colours[i]);
    }
  const SampleBuffer reference = buffer;
  buffer.updateActive(threshold, 100);
  std::vector<uint8_t> noisy(colours.size());
  for (uint32_t i : active) noisy[i] = reference.centreContrast(i) >= threshold;
  int edges = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = buffer.index(x, y);
      // Its own verdict, or those of most of its neighbours.
      int neighbours = 0, noisyNeighbours = 0;
      for (int ny = std::max(0, y - 1); ny <= std::min(h - 1, y + 1); ++ny)
        for (int nx = std::max(0, x - 1); nx <= std::min(w - 1, x + 1); ++nx) {
          if (nx == x && ny == y) continue;
          ++neighbours;
          noisyNeighbours += noisy[buffer.index(nx, ny)];
        }
      const bool expected =
          reference.active(i) && (noisy[i] || 2 * noisyNeighbours > neighbours);
      edges += noisy[i];
      EXPECT_EQ(buffer.active(i), expected) << x << "," << y << " at " << threshold;
    }
  EXPECT_GT(edges, 0) << threshold;
  EXPECT_LT(edges, static_cast<int>(active.size())) << threshold;
}

// The verdicts after the centre-first pass take each pair of neighbours
// once, and settle most pairs without their estimate; they must be
// centreContrast's, pixel by pixel: at the frame's borders, beside pixels
// outside the region, at a threshold an estimate meets exactly, and in a
// frame with a negative channel.
TEST(SampleBuffer, CentreVerdictsAreEachPixelsOwn) {
  const int w = 23, h = 17;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> shade(0, 5);
  std::uniform_real_distribution<float> jitter(0.f, 1e-7f);
  // Blocks of a few levels (most neighbours equal), some pixels a hair off
  // theirs, some with a bright blue.
  std::vector<int> block((h / 3 + 1) * (w / 4 + 1));
  for (int &b : block) b = shade(rng);
  std::vector<Color> frame;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v =
          block[(y / 3) * (w / 4 + 1) + x / 4] * 0.08f + (shade(rng) == 0 ? jitter(rng) : 0.f);
      frame.emplace_back(v, v * 0.5f, shade(rng) == 0 && v > 0.2f ? 1.f : v);
    }
  // The estimate of the first two neighbours that differ, as a threshold.
  double met = 0;
  for (size_t i = 0; i + 1 < frame.size() && met == 0; ++i)
    met = centrePairContrast(frame[i], frame[i + 1]);
  ASSERT_GT(met, 0);
  std::vector<Color> negative = frame;
  negative[w * 8 + 11].g = -0.05;
  for (const double threshold : {0.02, 0.1, 0.3, met})
    for (const bool cropped : {false, true}) {
      expectCentreVerdicts(frame, w, h, threshold, cropped);
      expectCentreVerdicts(negative, w, h, threshold, cropped);
    }
  // Channels that cancel: summed from the left pixel on, the pair's
  // brightness is 0.5 (estimate 0.70); from the right one, 0.005 (7.0).
  SampleBuffer cancelling(2, 1);
  cancelling.setCentre(0, {1e17, -1e17, 0.01});
  cancelling.setCentre(1, {1e17, -1e17, 1});
  EXPECT_LT(cancelling.centreContrast(0), 1);
  EXPECT_GT(cancelling.centreContrast(1), 1);
  EXPECT_EQ(cancelling.updateActive(1, 100), 2u);
}

// Runs of alike pixels (a background) are settled a run at a time: one
// pixel that differs, anywhere in or beside a run, in its row or the rows
// next to it, or a row unlike the one below it, must still leave every
// pixel its own verdict.
TEST(SampleBuffer, CentreVerdictsOfAlikeRunsAreEachPixelsOwn) {
  const int w = 53, h = 4;
  const Color background(0.2f, 0.3f, 0.4f), other(0.9f, 0.3f, 0.4f);
  auto expectOwn = [&](const std::function<Color(int, int)> &colourAt, const char *what) {
    SampleBuffer buffer(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) buffer.setCentre(buffer.index(x, y), colourAt(x, y));
    const std::vector<uint8_t> edges = buffer.centreEdges(0.1);
    int count = 0;
    for (size_t i = 0; i < edges.size(); ++i) {
      EXPECT_EQ(edges[i], buffer.centreContrast(i) >= 0.1) << "pixel " << i << ", " << what;
      count += edges[i];
    }
    EXPECT_GE(count, 4) << what; // the pixels on either side
  };
  for (int odd = 0; odd < w * h; ++odd)
    expectOwn([&](int x, int y) { return y * w + x == odd ? other : background; },
              ("one pixel unlike the rest: " + std::to_string(odd)).c_str());
  for (int row = 1; row < h; ++row)
    expectOwn([&](int, int y) { return y < row ? background : other; },
              ("rows unlike from " + std::to_string(row)).c_str());
}

TEST(SampleBuffer, VarianceOfABrightPixelSurvivesFloatSums) {
  // Samples 1000 + small noise over 8 passes: summed naively in float, the
  // sum of squares would cancel away; about the pixel's first mean it does
  // not (Film::variance is the samples' variance over their count).
  SampleBuffer buffer(1, 1);
  double sum = 0, squares = 0;
  int n = 0;
  for (int pass = 0; pass < 8; ++pass) {
    Color s, q;
    for (int k = 0; k < 16; ++k, ++n) {
      const double v = 1000 + 0.01 * ((n * 37) % 11 - 5);
      s += Color(v, v, v);
      q += Color(v * v, v * v, v * v);
      sum += v;
      squares += v * v;
    }
    buffer.add(0, s, q, 16);
  }
  Film film(1, 1);
  buffer.writeTo(film);
  const double mean = sum / n;
  double centred = 0;
  for (int k = 0; k < n; ++k) {
    const double v = 1000 + 0.01 * ((k * 37) % 11 - 5);
    centred += (v - mean) * (v - mean);
  }
  const double expected = centred / (n - 1) / n;
  EXPECT_NEAR(film.variance(0, 0).g, expected, 1e-3 * expected);
}

// The film taking the buffer's own sums and counts holds what a copy does:
// pixels without samples, with a centre, and with several.
TEST(SampleBuffer, MovedToAFilmAsWrittenToIt) {
  const int w = 9, h = 5;
  SampleBuffer buffer(w, h, SampleSet::Stratified, 1, 0, w, h); // column 0 never sampled
  for (int y = 0; y < h; ++y)
    for (int x = 1; x < w; ++x) {
      const size_t i = buffer.index(x, y);
      const double v = 0.1 * x + 0.03 * y;
      if ((x + y) % 3 == 0) {
        buffer.setCentre(i, {v, v / 3, 1.7});
        continue;
      }
      const uint32_t n = 4 + x;
      buffer.add(i, Color(v, 2 * v, 0.5) * n, Color(v * v + 0.01, 4 * v * v, 0.3) * n, n);
    }
  Film copied(w, h), moved(w, h);
  buffer.writeTo(copied);
  std::move(buffer).moveTo(moved);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      EXPECT_EQ(moved.get(x, y), copied.get(x, y)) << x << "," << y;
      EXPECT_EQ(moved.variance(x, y), copied.variance(x, y)) << x << "," << y;
      EXPECT_EQ(moved.error(x, y), copied.error(x, y)) << x << "," << y;
      EXPECT_EQ(moved.sampleCount(x, y), copied.sampleCount(x, y)) << x << "," << y;
    }
  EXPECT_EQ(moved.sampleCount(0, 2), 0u);
  EXPECT_GT(moved.error(2, 0), 0.f);
  EXPECT_EQ(moved.report.samples, copied.report.samples);
  EXPECT_EQ(moved.report.meanError, copied.report.meanError);
  EXPECT_EQ(moved.report.maxPixelSamples, copied.report.maxPixelSamples);
}

// moveTo sums the report itself, without reading the refined pixels'
// estimates back (their pages stay unmapped): the same report as the film
// it leaves gives summarizeSampling, refined pixels (estimate 0) and all.
TEST(SampleBuffer, MovingReportsWhatTheFilmHolds) {
  const int w = 11, h = 6;
  SampleBuffer buffer(w, h, SampleSet::Stratified, 0, 0, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = buffer.index(x, y);
      const double v = 0.07 * x + 0.05 * y;
      switch ((x + 2 * y) % 4) {
      case 0:
        buffer.setCentre(i, {v, v / 2, 0.9});
        break;
      case 1:
        buffer.setCentre(i, {v, 0.2, 0.4});
        buffer.setRefined(i, {v, 0.3, 0.5}, 5 + x);
        break;
      case 2: {
        const uint32_t n = 3 + y;
        buffer.add(i, Color(v, 2 * v, 0.5) * n, Color(v * v + 0.02, 4 * v * v, 0.3) * n, n);
        break;
      }
      default:
        break; // no samples
      }
    }
  Film moved(w, h);
  std::move(buffer).moveTo(moved);
  const SamplingReport report = moved.report;
  summarizeSampling(moved);
  EXPECT_EQ(report.samples, moved.report.samples);
  EXPECT_EQ(report.maxPixelSamples, moved.report.maxPixelSamples);
  EXPECT_EQ(report.hasError, moved.report.hasError);
  EXPECT_EQ(report.meanError, moved.report.meanError);
  EXPECT_EQ(report.maxError, moved.report.maxError);
  EXPECT_TRUE(report.hasError);
  EXPECT_GT(report.meanError, 0);
  EXPECT_EQ(moved.error(1, 0), 0.f); // a refined pixel
}

} // namespace
} // namespace lray
