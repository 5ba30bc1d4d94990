// Pipeline: render. The edge lattice (--edge-lattice; lua/README.md,
// "Pixel sampling"): after the centre-first pass, each pixel that adaptive
// sampling would refine is a square cell, cut into four where the colours
// at its corners (and its centre, where known) differ enough for the cell's
// area (contrast times area at least the noise threshold), down to cells
// 2^-depth of a pixel wide. A cell left whole counts as the mean of those
// points, times its area. An edge costs rays only in the cells it crosses,
// so on a straight edge the error falls about as n^-1.5 in a pixel's rays
// n, where that of any fixed set of equally weighted points, Sobol's too,
// falls no faster than n^-0.75 (Beck 1987, discrepancy for half-planes).
// The price: detail between lattice points that no corner sees is missed,
// as with POV-Ray's +AM2, whose corner rays and recursion this follows;
// here the centre-first pass chooses the pixels, only theirs are traced,
// and a cell's threshold grows as it shrinks.
#pragma once

#include "math/color.h"
#include "render/sample_buffer.h"
#include "util/zeroed_vector.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace lray {

/// The lattice of one tile's refined pixels, refined round by round: each
/// round, the open cells' corners are traced (pending, set), then judged.
/// Neighbouring pixels share the points on their common side.
class PixelLattice {
public:
  /// A lattice point: (i, j) / 2^depth of a pixel from the tile's top-left
  /// corner.
  struct Point {
    uint16_t i, j;
  };

  /// Starts over for a tile of `width` x `height` pixels, with cells
  /// 2^-depth of a pixel wide at the finest (1 <= depth <= 8; the tile's
  /// lattice takes 13 bytes a point and a third more for the coarser levels:
  /// 4.6 MB for 16 x 16 pixels at 5, mapped only where used).
  void reset(int depth, int width, int height) {
    for (uint32_t k : touched_) known_[k] = kUnknown;
    touched_.clear();
    depth_ = depth;
    cells_ = 1u << depth;
    // The points by level: level L's grid holds every point whose
    // coordinates are multiples of 2^(depth - L), and each point lives in
    // the first level that holds it. A cell cut once or twice (most are)
    // then keeps its points in the small grids, a few pages a thread,
    // not one or two pages per row of the finest grid: a page mapped is a
    // fault and the zeroing of 4 KB (about 1.5 us on bench/README.md's
    // machine), and a small frame's lattice pass maps hundreds.
    size_t points = 0;
    for (int level = 0; level <= depth; ++level) {
      const uint32_t n = 1u << level;
      levelStart_[level] = static_cast<uint32_t>(points);
      levelSide_[level] = static_cast<uint32_t>(width) * n + 1;
      points += static_cast<size_t>(levelSide_[level]) * (static_cast<uint32_t>(height) * n + 1);
    }
    if (known_.size() < points) {
      // Left uninitialised, and the states zero from calloc: a point's
      // value is read only once it is known, so pages are mapped only
      // where pixels are refined.
      values_.reset(new Value[points]);
      known_ = ZeroedVector<uint8_t>(points);
    }
    open_.clear();
    sums_.clear();
    origin_.clear();
    used_.clear();
    pixelWords_ = ((cells_ + 1) * (cells_ + 1) + 63) / 64;
  }
  /// Adds the tile's pixel (x, y), whose centre sample is `centre` (a
  /// lattice point, known), or that has none (`traced` false: a centre
  /// --sparse-centres filled, traced here only if the pixel is cut);
  /// returns its index. The pixel is an open cell.
  uint32_t add(int x, int y, const Color &centre, bool traced = true) {
    const uint32_t p = static_cast<uint32_t>(sums_.size());
    const uint16_t i = static_cast<uint16_t>(x * cells_), j = static_cast<uint16_t>(y * cells_);
    const uint16_t half = static_cast<uint16_t>(cells_ / 2);
    open_.push_back({p, i, j, static_cast<uint16_t>(cells_)});
    sums_.emplace_back();
    used_.resize(used_.size() + pixelWords_, 0);
    origin_.push_back({i, j});
    if (traced) {
      const uint32_t c = slot(i + half, j + half);
      values_[c] = Value::of(centre);
      known_[c] = kKnown;
      touched_.push_back(c);
      use(p, half, half);
    }
    return p;
  }
  uint32_t pixels() const { return static_cast<uint32_t>(sums_.size()); }
  /// The width of the finest cells, in pixels.
  double step() const { return 1.0 / cells_; }
  /// A point's index in the tile's lattice: in the coarsest level's grid
  /// that holds it (reset), row by row.
  uint32_t slot(uint32_t i, uint32_t j) const {
    // Both coordinates are multiples of 2^shift; shift <= depth_ (cells_
    // is 2^depth_).
    const int shift = std::countr_zero(i | j | cells_);
    const int level = depth_ - shift;
    return levelStart_[level] + (j >> shift) * levelSide_[level] + (i >> shift);
  }

  /// Appends to `out` the points the open cells' corners need, each once.
  void pending(std::vector<Point> &out) {
    for (const Cell &c : open_)
      for (int k = 0; k < 4; ++k) {
        const uint16_t i = c.i + (k & 1 ? c.size : 0), j = c.j + (k & 2 ? c.size : 0);
        use(c.pixel, i - origin_[c.pixel].i, j - origin_[c.pixel].j);
        const uint32_t s = slot(i, j);
        if (known_[s] != kUnknown) continue;
        known_[s] = kQueued;
        touched_.push_back(s);
        out.push_back({i, j});
      }
  }
  /// The colour traced at a pending point.
  void set(const Point &q, const Color &c) {
    const uint32_t s = slot(q.i, q.j);
    values_[s] = Value::of(c);
    known_[s] = kKnown;
  }

  /// Judges the open cells, whose corners are known: one whose points'
  /// contrast (contrastOf, below) times its area reaches `threshold` is
  /// cut into four, open for the next round (unless it is a finest cell);
  /// another adds its share to its pixel's colour. Returns whether any
  /// cell is open.
  bool judge(double threshold);

  /// Pixel p's colour, once no cell is open, and the lattice points it
  /// rests on (its centre among them; a point on the side of two pixels
  /// counts for both, though it was traced once).
  const Color &colour(uint32_t p) const { return sums_[p]; }
  uint32_t points(uint32_t p) const {
    uint32_t n = 0;
    for (size_t w = 0; w < pixelWords_; ++w) n += std::popcount(used_[p * pixelWords_ + w]);
    return n;
  }

private:
  struct Cell {
    uint32_t pixel;
    uint16_t i, j, size; ///< top-left corner and width, in finest cells
  };
  static constexpr uint8_t kUnknown = 0, kQueued = 1, kKnown = 2;
  /// A point's colour in float (the film's sums are float too): a tile's
  /// lattice at depth 5 is 513 x 513 of them.
  struct Value {
    float r, g, b;
    static Value of(const Color &c) {
      return {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b)};
    }
    Color colour() const { return {r, g, b}; }
  };
  /// Marks the point (i, j) of pixel p's own lattice as one it rests on.
  void use(uint32_t p, uint32_t i, uint32_t j) {
    const uint32_t bit = j * (cells_ + 1) + i;
    used_[p * pixelWords_ + bit / 64] |= uint64_t{1} << (bit % 64);
  }

  int depth_ = 1;
  uint32_t cells_ = 2; ///< finest cells along a pixel's side
  static constexpr int kMaxDepth = 8;
  /// Per level (reset), where its grid starts and its points along the
  /// tile's width.
  uint32_t levelStart_[kMaxDepth + 1] = {}, levelSide_[kMaxDepth + 1] = {};
  std::unique_ptr<Value[]> values_; ///< the tile's points (slot)
  ZeroedVector<uint8_t> known_;  ///< the same points' states
  std::vector<uint32_t> touched_; ///< the points whose state is set
  std::vector<Cell> open_, next_;
  std::vector<Color> sums_;
  std::vector<Point> origin_;    ///< per pixel, its top-left lattice point
  std::vector<uint64_t> used_;   ///< per pixel, pixelWords_ words: the points it uses
  size_t pixelWords_ = 1;
};

/// The contrast of n points (2 to 5), point(k) for k < n: half the sum
/// over the channels of their range, over the square root of their mean
/// brightness; for two points, centrePairContrast. (`point` reads them
/// where they lie: a copy of them would be zeroed first.)
template <class Point>
[[gnu::always_inline]] inline double contrastOf(int n, const Point &point) {
  Color lo = point(0), hi = lo, sum = lo;
  for (int k = 1; k < n; ++k) {
    const Color &p = point(k);
    lo = {std::min(lo.r, p.r), std::min(lo.g, p.g), std::min(lo.b, p.b)};
    hi = {std::max(hi.r, p.r), std::max(hi.g, p.g), std::max(hi.b, p.b)};
    sum += p;
  }
  const double range = (hi.r - lo.r) + (hi.g - lo.g) + (hi.b - lo.b);
  if (range == 0) return 0; // no edge, and no square root
  const double brightness = std::max(0.0, (sum.r + sum.g + sum.b) / n);
  return 0.5 * range / (1e-4 + std::sqrt(brightness));
}

/// How far a square's colour departs from changing linearly across it, in
/// contrastOf's units, from its corners point(0) to point(3) (reading
/// order: top-left, top-right, bottom-left, bottom-right) and its centre
/// point(4): per channel the larger of twice the centre's distance from the
/// corners' mean and the corners' twist (top-left + bottom-right - the
/// other two), summed, halved, over the square root of the five points'
/// mean brightness. 0 where the colour is a linear function of position: a
/// shading or texture gradient, where the points' mean is the square's mean
/// already. A straight edge across the square, with the centre on one side
/// and some corner on the other, departs by at least its contrastOf.
template <class Point>
[[gnu::always_inline]] inline double departureOf(const Point &point) {
  const Color a = point(0), b = point(1), c = point(2), d = point(3), m = point(4);
  const Color sum = a + b + c + d;
  const Color off = m * 4.0 - sum; // 4 (centre - the corners' mean)
  const Color twist = a + d - b - c;
  auto channel = [](double o, double t) { return std::max(0.5 * std::abs(o), std::abs(t)); };
  const double departure =
      channel(off.r, twist.r) + channel(off.g, twist.g) + channel(off.b, twist.b);
  const double brightness = std::max(0.0, ((sum.r + m.r) + (sum.g + m.g) + (sum.b + m.b)) / 5);
  return 0.5 * departure / (1e-4 + std::sqrt(brightness));
}

inline bool PixelLattice::judge(double threshold) {
  next_.clear();
  const double finest = 1.0 / (static_cast<double>(cells_) * cells_);
  for (const Cell &c : open_) {
    uint32_t at[5]; // the slots of the cell's points
    int n = 0;
    for (int k = 0; k < 4; ++k)
      at[n++] = slot(c.i + (k & 1 ? c.size : 0), c.j + (k & 2 ? c.size : 0));
    const uint16_t half = c.size / 2;
    // The centre is known for the whole pixel (the centre-first pass).
    if (c.size > 1 && known_[slot(c.i + half, c.j + half)] == kKnown)
      at[n++] = slot(c.i + half, c.j + half);
    auto point = [&](int k) { return values_[at[k]].colour(); };
    // Cut where the points' contrast times the cell's area (in pixels)
    // reaches the threshold: about the most the cell's detail can move its
    // pixel. A cell costs about as many rays at any size, so the deeper
    // ones are cut only for the stronger edges.
    const double width = static_cast<double>(c.size) / cells_;
    const double least = threshold / (width * width);
    // A whole pixel with its centre is cut only where its colour also
    // departs from linear by half as much (departureOf): a gradient's
    // points already give its mean, and an edge departs by its contrast.
    // Half, not all: five points see a bend in the shading only coarsely,
    // and smooth spheres lost more error than rays at the full threshold.
    if (c.size > 1 && contrastOf(n, point) >= least &&
        (n < 5 || departureOf(point) >= 0.5 * least)) {
      for (int k = 0; k < 4; ++k)
        next_.push_back({c.pixel, static_cast<uint16_t>(c.i + (k & 1 ? half : 0)),
                         static_cast<uint16_t>(c.j + (k & 2 ? half : 0)), half});
      continue;
    }
    Color mean;
    for (int k = 0; k < n; ++k) mean += point(k);
    sums_[c.pixel] += mean * (static_cast<double>(c.size) * c.size * finest / n);
  }
  open_.swap(next_);
  return !open_.empty();
}

} // namespace lray
