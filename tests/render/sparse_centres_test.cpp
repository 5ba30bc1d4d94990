// Tests for sparse centres (--sparse-centres; render/sparse_centres.h and
// its pass in tile_renderer_impl.h): which centres a tile traces and which
// it fills, and whole renders: deterministic for any thread count, the same
// on both backends, a crop the same as the frame, the traced centres those
// of the plain centre pass, fewer camera rays at the same error.
#include "render/backends.h"
#include "render/pixel_lattice.h"
#include "render/render_films.h"
#include "render/silhouette_scene.h"
#include "render/sparse_centres.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>

namespace lray {
namespace {

using Centre = std::function<Color(int, int)>;

/// Runs a tile of `width` x `height` pixels (and the pixels `pastX`,
/// `pastY` beyond) whose centre (x, y) has colour f(x, y), as the render
/// pass does, checking that no centre is asked for twice or outside the
/// window; returns how many were traced.
int runTile(SparseCentres &sparse, const Centre &f, double threshold, int width = 16,
            int height = 16, int pastX = 1, int pastY = 1) {
  sparse.reset(width, height, pastX, pastY);
  std::set<std::pair<int, int>> asked;
  std::vector<SparseCentres::Point> points;
  for (;;) {
    points.clear();
    if (!sparse.next(threshold, points)) break;
    for (const auto &p : points) {
      EXPECT_LT(p.x, width + pastX);
      EXPECT_LT(p.y, height + pastY);
      EXPECT_TRUE(asked.insert({p.x, p.y}).second) << int(p.x) << "," << int(p.y);
      sparse.set(p, f(p.x, p.y));
    }
  }
  return static_cast<int>(asked.size());
}

TEST(SparseCentres, AFlatTileTracesOneCentreInFour) {
  SparseCentres sparse;
  const Color grey(0.3, 0.5, 0.7);
  // The even centres of the tile and of the row and column past it: 9 x 9.
  EXPECT_EQ(runTile(sparse, [&](int, int) { return grey; }, 0.1), 81);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_EQ(sparse.traced(x, y), x % 2 == 0 && y % 2 == 0) << x << "," << y;
      EXPECT_EQ(sparse.colour(x, y), grey);
    }
}

TEST(SparseCentres, AFlatTileAtThresholdZeroTracesEveryCentre) {
  // Alike neighbours fill a pixel only below a positive limit: at
  // threshold 0 (limit 0) nothing is filled, a plain tile neither.
  SparseCentres sparse;
  // Every pixel of the tile, and the even ones of the row and column past.
  EXPECT_EQ(runTile(sparse, [](int, int) { return Color(0.3, 0.5, 0.7); }, 0), 16 * 16 + 17);
}

TEST(SparseCentres, ZerosOfEitherSignAreOneColour) {
  // Neighbours equal in value, not in bits (0 and -0): still no contrast,
  // every pixel between them filled, with its first known neighbour's.
  SparseCentres sparse;
  auto f = [](int x, int y) { return (x + y) % 4 == 0 ? Color(-0.0, 0, 0) : Color(0, 0, 0); };
  EXPECT_EQ(runTile(sparse, f, 0.1), 81);
  EXPECT_TRUE(std::signbit(sparse.colour(1, 1).r)); // its diagonal (0, 0) holds -0
  EXPECT_FALSE(std::signbit(sparse.colour(3, 1).r)); // (2, 0) holds +0
}

TEST(SparseCentres, AStraightEdgeIsTracedAlongItsLengthAndNothingIsFilledWrong) {
  SparseCentres sparse;
  for (int edge = 1; edge < 15; ++edge) {
    // White up to column `edge`, black after; a horizontal edge as well.
    auto f = [&](int x, int y) { return x <= edge && y <= 9 ? Color(1, 1, 1) : Color(); };
    const int traced = runTile(sparse, f, 0.1);
    EXPECT_LT(traced, 81 + 2 * 16 + 2 * 16 + 16) << edge;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        EXPECT_EQ(sparse.colour(x, y), f(x, y)) << x << "," << y << " edge " << edge;
        // The two columns and rows either side of the edges are traced.
        if ((x == edge || x == edge + 1) && y <= 9) {
          EXPECT_TRUE(sparse.traced(x, y)) << x << "," << y;
        }
        if ((y == 9 || y == 10) && x <= edge) {
          EXPECT_TRUE(sparse.traced(x, y)) << x << "," << y;
        }
      }
  }
}

TEST(SparseCentres, ASlowRampIsFilledExactlyAndASteepOneTraced) {
  SparseCentres sparse;
  // A linear ramp: the mean of a centre's opposite neighbours is its value.
  for (double slope : {0.00002, 0.02}) {
    auto f = [&](int x, int y) { return Color(0.5 + slope * x, 0.5 + slope * y, 0.5); };
    const int traced = runTile(sparse, f, 0.1);
    // The slow one: the even centres alone; the steep one: every centre
    // of the tile too.
    EXPECT_EQ(traced, slope < 0.001 ? 81 : 256 + 17) << slope;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const Color c = sparse.colour(x, y), want = f(x, y);
        EXPECT_NEAR(c.r, want.r, 1e-12);
        EXPECT_NEAR(c.g, want.g, 1e-12);
      }
  }
}

TEST(SparseCentres, FillsBelowAFifthOfTheThresholdUpToABound) {
  // A ramp of slope s in red and green: between four diagonal neighbours
  // (area 4) its contrast times the area is about 6.5 s, between four
  // straight ones (area 2) about 3.3 s. The fill limit: a fifth of the
  // threshold, at most SparseCentres::kFillMost (0.03).
  SparseCentres sparse;
  auto ramp = [](double slope) {
    return [slope](int x, int y) { return Color(0.5 + slope * x, 0.5 + slope * y, 0.5); };
  };
  // Threshold 0.1, limit 0.02: s = 0.002 is filled in both rounds (it was
  // traced under a 3 % share, 0.003).
  EXPECT_EQ(runTile(sparse, ramp(0.002), 0.1), 81);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) EXPECT_NEAR(sparse.colour(x, y).r, 0.5 + 0.002 * x, 1e-12);
  // Threshold 1: a fifth would fill s = 0.005 (6.5 s = 0.033) everywhere;
  // the bound (0.03) traces the diagonal round and fills the straight one.
  EXPECT_EQ(runTile(sparse, ramp(0.005), 1), 81 + 64);
  EXPECT_EQ(runTile(sparse, ramp(0.003), 1), 81);
}

TEST(SparseCentres, AtTheFramesEdgesTheLastOddCentresAreTraced) {
  // A tile of 14 x 11 pixels at the frame's right and bottom edges: no
  // centre past it; the last column is odd, the last row even.
  SparseCentres sparse;
  const Color grey(0.4, 0.4, 0.4);
  runTile(sparse, [&](int, int) { return grey; }, 0.1, 14, 11, 0, 0);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 14; ++x) {
      // Odd centres between four diagonal ones need all four (the last
      // column's have two), the others three of their four neighbours (the
      // last column's corners have two).
      const bool expected = (x % 2 == 0 && y % 2 == 0) || (x == 13 && y % 2 == 1) ||
                            (x == 13 && (y == 0 || y == 10));
      EXPECT_EQ(sparse.traced(x, y), expected) << x << "," << y;
      EXPECT_EQ(sparse.colour(x, y), grey);
    }
}

TEST(SparseCentres, APixelWithAFilledCentreTakesItsCornersAlone) {
  // On the edge lattice, a filled centre is not a point: a flat pixel
  // takes its four corners, a cut one traces its centre too.
  for (bool flat : {true, false}) {
    PixelLattice lattice;
    lattice.reset(3, 1, 1);
    lattice.add(0, 0, Color(0.5, 0.5, 0.5), false);
    auto f = [&](double u) { return flat || u < 0.3 ? Color(0.5, 0.5, 0.5) : Color(); };
    std::vector<PixelLattice::Point> points;
    bool centreTraced = false;
    do {
      points.clear();
      lattice.pending(points);
      for (const auto &q : points) {
        centreTraced |= q.i == 4 && q.j == 4;
        lattice.set(q, f(q.i * lattice.step()));
      }
    } while (lattice.judge(1e-3));
    if (flat) {
      EXPECT_EQ(lattice.points(0), 4u);
      EXPECT_FALSE(centreTraced);
      EXPECT_NEAR(lattice.colour(0).r, 0.5, 1e-7);
    } else {
      EXPECT_TRUE(centreTraced);
      EXPECT_GT(lattice.points(0), 9u);
    }
  }
}

// Whole renders.

constexpr int kWidth = 48, kHeight = 32;

FrameSettings settings(double threshold, bool sparse, int depth = 0) {
  FrameSettings fs = test::centreFirstSettings(kWidth, kHeight, threshold, 64);
  fs.adaptiveSettings.latticeDepth = depth;
  fs.adaptiveSettings.sparseCentres = sparse;
  return fs;
}

using test::render;
using test::rmse;

class SparseCentresRender : public test::SilhouetteRender {};

TEST_P(SparseCentresRender, SameBytesForAnyThreadCountAndOnBothBackends) {
  for (int depth : {0, 4}) {
    const FrameSettings fs = settings(0.05, true, depth);
    const Film one = test::renderOnThreads(scene, *accel, fs, 1);
    const Film many = test::renderOnThreads(scene, *accel, fs, 4);
    EXPECT_EQ(one.data(), many.data()) << depth;
    EXPECT_EQ(render(scene, *makeAccelerator(otherBackend(), scene), fs).data(), one.data())
        << depth;
  }
}

TEST_P(SparseCentresRender, ACropIsTheFramesPixels) {
  expectCropIsTheFramesPixels(settings(0.05, true, 4));
}

TEST_P(SparseCentresRender, FewerCameraRaysAtTheSameError) {
  // A high threshold: the centres and a few Sobol passes at the edges.
  const Film reference = render(scene, *accel, [] {
    FrameSettings fs = settings(0, false);
    fs.adaptive = false;
    fs.samples = 16;
    return fs;
  }());
  RayCounts plain, sparse;
  const Film plainFilm = render(scene, *accel, settings(1, false), &plain);
  const Film sparseFilm = render(scene, *accel, settings(1, true), &sparse);
  EXPECT_LT(sparse.camera, 0.6 * plain.camera) << sparse.camera << " " << plain.camera;
  EXPECT_LT(rmse(sparseFilm, reference), 1.01 * rmse(plainFilm, reference));
  // Every pixel is the plain pass's centre or close to it: the traced
  // centres are the same rays.
  int same = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Color a = sparseFilm.get(x, y), b = plainFilm.get(x, y);
      same += a == b;
      EXPECT_NEAR(a.r, b.r, 0.01) << x << "," << y;
      EXPECT_NEAR(a.g, b.g, 0.01) << x << "," << y;
    }
  EXPECT_GE(same, kWidth * kHeight / 4);
}

INSTANTIATE_TEST_SUITE_P(Backends, SparseCentresRender,
                         ::testing::Values(BackendKind::Embree, BackendKind::KdTree),
                         [](const auto &param) { return std::string(backendName(param.param)); });

} // namespace
} // namespace lray
