// Pipeline: render. Sparse centres (--sparse-centres; lua/README.md,
// "Pixel sampling"): the centre-first pass of one tile traces every other
// pixel centre of every other row, and fills each pixel between traced ones
// whose colours agree with their mean instead of tracing it, in two rounds:
// first the pixels between four diagonal neighbours (a cell two pixels
// wide), then those between four neighbours up, down, left and right (two
// of them traced, two from the first round). A pixel whose neighbours
// differ is traced. Where the picture is smooth (a plain background, a
// slowly shaded surface) three centres in four cost no ray; an edge or a
// texture's detail is traced as before. What it misses: a line thinner than
// two pixels that falls between traced centres of one colour (which every
// centre would have seen), hence the small bound on the fill below.
#pragma once

#include "math/color.h"
#include "render/pixel_lattice.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace lray {

class SparseCentres {
public:
  /// A pixel of the tile, or of the row and column just past it (x or y =
  /// the tile's side): coordinates from the tile's top-left pixel.
  struct Point {
    uint8_t x, y;
  };
  /// The tile's side in pixels, and the window it fills from: the tile and
  /// the row and column past it (their even pixels are traced too, so that
  /// the tile's last odd row and column lie between traced centres).
  static constexpr int kSide = 16, kWindow = kSide + 1;
  /// A cell whose contrast times its area stays below kFillShare of the
  /// noise threshold, and below kFillMost, is filled. The share lets the
  /// centres of a smooth gradient (a marble sphere's veins, a soft shadow)
  /// be filled at low thresholds, where the passes after it refine edges
  /// anyway; the bound keeps high thresholds from filling across detail
  /// that its neighbours do not show (a thin line between them): above
  /// 0.03 (3 % of the threshold 1, as before) a distant checkerboard's
  /// aliasing shows. On the bench scenes, the same error with up to a
  /// fifth fewer camera rays than a 3 % share at every threshold
  /// (bench/README.md, "Fills at low thresholds").
  static constexpr double kFillShare = 0.2, kFillMost = 0.03;

  static double fillLimit(double threshold) {
    return std::min(kFillShare * threshold, kFillMost);
  }

  /// Starts the tile of `width` x `height` pixels (at most kSide each)
  /// whose window reaches `past` more pixels right and below within the
  /// frame (0 or 1 each; 0 at the frame's right or bottom edge).
  void reset(int width, int height, int pastX, int pastY) {
    width_ = width;
    height_ = height;
    spanX_ = width + pastX;
    spanY_ = height + pastY;
    round_ = 0;
    state_.fill(kUnknown);
  }

  /// Appends to `out` the pixels to trace next (round 0: the even pixels of
  /// even rows of the window; 1 and 2: the pixels of that round whose
  /// neighbours differ, the others filled with their mean), after
  /// set() has given the last round's colours. A pixel is filled where its
  /// neighbours' contrast (contrastOf, render/pixel_lattice.h) times the
  /// area between them (in pixels) stays below fillLimit(`threshold`).
  /// Returns false once every pixel of the tile is known.
  bool next(double threshold, std::vector<Point> &out);
  void set(const Point &p, const Color &c) {
    value_[slot(p.x, p.y)] = c;
    state_[slot(p.x, p.y)] = kTraced;
  }

  /// Pixel (x, y)'s colour once next() has returned false, and whether it
  /// was traced (or filled).
  const Color &colour(int x, int y) const { return value_[slot(x, y)]; }
  bool traced(int x, int y) const { return state_[slot(x, y)] == kTraced; }

private:
  static constexpr uint8_t kUnknown = 0, kTraced = 1, kFilled = 2;
  static int slot(int x, int y) { return y * kWindow + x; }
  /// Fills pixel (x, y) from its known neighbours at offsets `d` (two
  /// opposite pairs: d[0] and d[3], d[1] and d[2]) when there are at least
  /// `least` of them (so at least one whole pair) and their contrast times
  /// `area` is below fillLimit(threshold); else appends it to `out`.
  void fillOrTrace(int x, int y, const int (*d)[2], int least, double area, double threshold,
                   std::vector<Point> &out);

  int width_ = 0, height_ = 0, spanX_ = 0, spanY_ = 0, round_ = 0;
  std::array<Color, kWindow * kWindow> value_;
  std::array<uint8_t, kWindow * kWindow> state_{};
};

inline void SparseCentres::fillOrTrace(int x, int y, const int (*d)[2], int least, double area,
                                       double threshold, std::vector<Point> &out) {
  int at[4];    // the slots of the known neighbours, in d's order
  int slots[4]; // per offset, its neighbour's slot, or -1
  int n = 0;
  if (x >= 1 && y >= 1 && x + 1 < width_ && y + 1 < height_) {
    // Inside the tile (most pixels): every neighbour is known, traced in
    // round 0 (the even pixels of even rows) or settled in round 1 (the
    // odd pixels of odd rows; next() goes round by round).
    for (int k = 0; k < 4; ++k) at[k] = slots[k] = slot(x + d[k][0], y + d[k][1]);
    n = 4;
  } else {
    for (int k = 0; k < 4; ++k) {
      const int nx = x + d[k][0], ny = y + d[k][1];
      const bool known = nx >= 0 && ny >= 0 && nx < spanX_ && ny < spanY_ &&
                         state_[slot(nx, ny)] != kUnknown;
      slots[k] = known ? slot(nx, ny) : -1;
      if (known) at[n++] = slots[k];
    }
  }
  const double contrast =
      n >= least ? contrastOf(n, [&](int k) -> const Color & { return value_[at[k]]; }) : 1e300;
  if (contrast * area >= fillLimit(threshold)) {
    out.push_back({static_cast<uint8_t>(x), static_cast<uint8_t>(y)});
    return;
  }
  // Equal neighbours give their very colour (a plain background stays
  // exactly its colour); others the mean of the opposite pairs (d[0] and
  // d[3], d[1] and d[2]) whose both ends are known, which a linear ramp
  // fills exactly.
  Color mean = value_[at[0]];
  if (contrast > 0) {
    mean = Color();
    int pairs = 0;
    for (int k = 0; k < 2; ++k)
      if (slots[k] >= 0 && slots[3 - k] >= 0) {
        mean += value_[slots[k]] + value_[slots[3 - k]];
        ++pairs;
      }
    mean = mean / (2.0 * pairs);
  }
  value_[slot(x, y)] = mean;
  state_[slot(x, y)] = kFilled;
}

inline bool SparseCentres::next(double threshold, std::vector<Point> &out) {
  static constexpr int diagonal[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  static constexpr int straight[4][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}};
  switch (round_++) {
  case 0:
    for (int y = 0; y < spanY_; y += 2)
      for (int x = 0; x < spanX_; x += 2) out.push_back({uint8_t(x), uint8_t(y)});
    return true;
  case 1:
    // Between four traced centres: a cell two pixels wide (area 4).
    for (int y = 1; y < height_; y += 2)
      for (int x = 1; x < width_; x += 2) fillOrTrace(x, y, diagonal, 4, 4, threshold, out);
    return true;
  case 2:
    // Between four known centres a pixel away (area 2); at the tile's top
    // and left sides three (the fourth is the next tile's).
    for (int y = 0; y < height_; ++y)
      for (int x = 1 - (y & 1); x < width_; x += 2)
        fillOrTrace(x, y, straight, 3, 2, threshold, out);
    return true;
  default:
    return false;
  }
}

} // namespace lray
