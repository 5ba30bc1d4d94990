// Pipeline: render. See sample_buffer.h.
#include "render/sample_buffer.h"

#include "render/flush_to_zero.h"
#include "render/pixel_error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace lray {

SampleBuffer::SampleBuffer(int width, int height, SampleSet samples, int x0, int y0, int x1,
                           int y1)
    : width_(width), height_(height), samples_(samples),
      region_{x1 > x0 && y1 > y0 ? PixelWindow{x0, y0, x1, y1} : PixelWindow{0, 0, width, height}},
      sums_(static_cast<size_t>(width) * height * 3),
      squares_(static_cast<size_t>(width) * height * kSquareFloats),
      count_(static_cast<size_t>(width) * height), active_(static_cast<size_t>(width) * height),
      centreOnly_(static_cast<size_t>(width) * height),
      refined_(static_cast<size_t>(width) * height) {}

bool SampleBuffer::anyActive(int x0, int y0, int x1, int y1) const {
  if (wholeRegionActive_)
    return x0 < region_.x1 && region_.x0 < x1 && y0 < region_.y1 && region_.y0 < y1;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      if (active_[index(x, y)]) return true;
  return false;
}

double SampleBuffer::error(size_t i) const {
  if (count_[i] < 2) return 0;
  return pixelError(mean(i), variance(i), count_[i], samples_);
}

Color SampleBuffer::variance(size_t i) const {
  const uint32_t n = count_[i];
  if (n < 2) return {}; // (and a centre's squares are never read)
  const float *s = &sums_[i * 3];
  const float *q = &squares_[i * kSquareFloats];
  const Color shifted = Color(s[0], s[1], s[2]) - Color(q[3], q[4], q[5]) * n;
  return varianceOfMean(shifted, {q[0], q[1], q[2]}, n);
}

Color SampleBuffer::mean(size_t i) const {
  const float *s = &sums_[i * 3];
  // One sample (a centre) is its own mean: no division, the same value.
  if (count_[i] == 1) return {s[0], s[1], s[2]};
  const double n = count_[i];
  return {s[0] / n, s[1] / n, s[2] / n};
}

double SampleBuffer::centreContrast(size_t i) const {
  const int x = static_cast<int>(i % static_cast<size_t>(width_));
  const int y = static_cast<int>(i / static_cast<size_t>(width_));
  const Color c = mean(i);
  double most = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
      const size_t j = index(nx, ny);
      if (j != i && count_[j]) most = std::max(most, centrePairContrast(c, mean(j)));
    }
  return most;
}

namespace {

// centreEdges' bits of a pixel, for its pairs with the neighbours right of
// it and below it: bit 2k, the pixel's verdict against neighbour k; bit
// 2k + 1, the neighbour's against it.
enum CentrePair { kRight, kDownLeft, kDown, kDownRight };
constexpr uint8_t seenFromPixel(CentrePair k) { return uint8_t(1u << (2 * k)); }
constexpr uint8_t seenFromNeighbour(CentrePair k) { return uint8_t(2u << (2 * k)); }

/// The verdicts on a pair of different centres c and d: bit 0,
/// centrePairContrast(c, d) >= threshold; bit 1, (d, c)'s.
[[gnu::noinline]] unsigned pairVerdictsBothWays(const Color &c, const Color &d, double threshold) {
  return unsigned(centrePairContrast(c, d) >= threshold) |
         unsigned(centrePairContrast(d, c) >= threshold) << 1;
}

/// pairVerdicts' first test on the pair (c, d), with limit = 0.98 t^2:
/// half their difference, squared, below limit times their brightness.
[[gnu::always_inline]] inline bool pairQuiet(double cr, double cg, double cb, double dr, double dg,
                                             double db, double limit) {
  const double half = 0.5 * (std::abs(cr - dr) + std::abs(cg - dg) + std::abs(cb - db));
  const double brightness = (cr + cg + cb + dr + dg + db) / 2;
  return half * half < limit * brightness;
}

/// pairVerdictsBothWays, in a frame whose channels may be negative
/// (`signedColours`) or not. Without one, the brightness's rounding,
/// whichever way it is summed, is some 1e-16 of it: a pair well below the
/// threshold is settled without the square root and division, and one
/// away from it takes the same verdict both ways.
inline unsigned pairVerdicts(const Color &c, const Color &d, double threshold,
                             bool signedColours) {
  if (signedColours) return pairVerdictsBothWays(c, d, threshold);
  if (pairQuiet(c.r, c.g, c.b, d.r, d.g, d.b, 0.98 * threshold * threshold)) return 0;
  const double contrast = centrePairContrast(c, d);
  if (std::abs(contrast - threshold) <= 1e-9 * threshold)
    return pairVerdictsBothWays(c, d, threshold);
  return contrast >= threshold ? 3 : 0;
}

/// For pixels x0 to x1 - 1 of a row inside the frame (rows y and y + 1 of
/// sums `s0`, `s1` and counts `n0`, `n1`; 0 < x0 < x1 < the width):
/// quiet[x] = 1 where pixel x and the four neighbours of its pairs hold one
/// sample each and every pair's colours differ by less than pairVerdicts'
/// first test lets through, so that the pixel's pair bits are 0 in a frame
/// without negative channels. The same operations as pairVerdicts, lane by
/// lane in a loop the compiler vectorises: a shaded floor, where no two
/// neighbours are alike, is settled without a branch per pair.
void quietPixels(const float *s0, const float *s1, const uint32_t *n0, const uint32_t *n1, int x0,
                 int x1, double threshold, std::vector<double> &scratch, uint8_t *quiet) {
  // The colours of columns x0 - 1 to x1, channel by channel.
  const int n = x1 - x0 + 2;
  scratch.resize(6 * static_cast<size_t>(n));
  double *r0 = scratch.data(), *g0 = r0 + n, *b0 = g0 + n, *r1 = b0 + n, *g1 = r1 + n,
         *b1 = g1 + n;
  for (int k = 0; k < n; ++k) {
    const int x = x0 - 1 + k;
    r0[k] = s0[3 * x], g0[k] = s0[3 * x + 1], b0[k] = s0[3 * x + 2];
    r1[k] = s1[3 * x], g1[k] = s1[3 * x + 1], b1[k] = s1[3 * x + 2];
  }
  const double limit = 0.98 * threshold * threshold;
  for (int k = 1; k + 1 < n; ++k) {
    const int x = x0 - 1 + k;
    const bool one = (n0[x] == 1) & (n0[x + 1] == 1) & (n1[x - 1] == 1) & (n1[x] == 1) &
                     (n1[x + 1] == 1);
    const double cr = r0[k], cg = g0[k], cb = b0[k];
    quiet[x] = one & pairQuiet(cr, cg, cb, r0[k + 1], g0[k + 1], b0[k + 1], limit) &
               pairQuiet(cr, cg, cb, r1[k - 1], g1[k - 1], b1[k - 1], limit) &
               pairQuiet(cr, cg, cb, r1[k], g1[k], b1[k], limit) &
               pairQuiet(cr, cg, cb, r1[k + 1], g1[k + 1], b1[k + 1], limit);
  }
}

} // namespace

std::vector<uint8_t> SampleBuffer::centreEdges(double threshold) const {
  // Each pair of neighbours once (the difference of their colours is the
  // same both ways, and 0 across most of a frame), then each pixel's
  // verdict gathered from its pairs: half the comparisons of one pixel at a
  // time, and both passes run by rows in parallel.
  const size_t pixels = count_.size();
  std::vector<uint8_t> pairs(pixels), edges(pixels);
  // Whether pixels i and j hold the same sums, bit for bit, and count
  // (differs: 0 if so): the same colour, no edge either way.
  auto differs = [&](size_t i, size_t j) {
    uint64_t a, b;
    uint32_t c, d;
    std::memcpy(&a, &sums_[i * 3], sizeof a);
    std::memcpy(&b, &sums_[j * 3], sizeof b);
    std::memcpy(&c, &sums_[i * 3 + 2], sizeof c);
    std::memcpy(&d, &sums_[j * 3 + 2], sizeof d);
    return (a ^ b) | (c ^ d) | (count_[i] ^ count_[j]);
  };
  auto same = [&](size_t i, size_t j) { return differs(i, j) == 0; };
  // Whether pixels i to i + n - 1 of a row hold the same sums and count.
  auto runAlike = [&](size_t i, size_t n) {
    return std::memcmp(&sums_[3 * i], &sums_[3 * (i + 1)], 3 * (n - 1) * sizeof(float)) == 0 &&
           std::memcmp(&count_[i], &count_[i + 1], (n - 1) * sizeof(uint32_t)) == 0;
  };
  constexpr int kRun = 16, kQuiet = 32;
  // Whether any channel is negative (or -0): its sign bit.
  uint32_t signs = 0;
  for (const float v : sums_) signs |= std::bit_cast<uint32_t>(v);
  const bool signedColours = signs >> 31;
  const size_t w = static_cast<size_t>(width_);
  tbb::parallel_for(0, height_, [&](int y) {
    setFlushToZero();
    // Inside the frame (every neighbour there), first whether the pixel's
    // four pairs are all plain, without a branch per pair: most of a frame.
    const bool inner = y + 1 < height_;
    int nextRun = 0;
    // quietPixels' flags for this row, from x = 1 up to quietTo, computed
    // kQuiet pixels at a time where runs are not alike.
    static thread_local std::vector<uint8_t> quiet;
    static thread_local std::vector<double> scratch;
    quiet.resize(w);
    int quietTo = 1;
    const size_t rowStart = index(0, y);
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      // A run of kRun pixels all plain: the run and its right neighbour
      // alike, the row below from one left of it to one right of it alike,
      // and the first pixel like the one below it (a frame's background in
      // a few wide compares, not four pair tests a pixel). Where a run is
      // not alike, the next is tried kRun pixels on.
      if (inner && x >= nextRun && x > 0 && x + kRun < width_) {
        if (runAlike(i, kRun + 1) && runAlike(i + w - 1, kRun + 2) && same(i, i + w)) {
          x += kRun - 1;
          continue;
        }
        nextRun = x + kRun;
      }
      if (inner && !signedColours && x > 0 && x + 1 < width_) {
        if (x >= quietTo) {
          quietTo = std::min(width_ - 1, x + kQuiet);
          quietPixels(&sums_[3 * rowStart], &sums_[3 * (rowStart + w)], &count_[rowStart],
                      &count_[rowStart + w], x, quietTo, threshold, scratch, quiet.data());
        }
        if (quiet[x]) continue;
      }
      if (!count_[i]) continue;
      if (inner && x > 0 && x + 1 < width_ &&
          (differs(i, i + 1) | differs(i, i + w - 1) | differs(i, i + w) |
           differs(i, i + w + 1)) == 0)
        continue;
      const bool right = x + 1 < width_, down = y + 1 < height_;
      // The pixel's pairs (CentrePair order) without an edge: no neighbour
      // there, or one of the same colour. Most of a frame has only those.
      const size_t neighbour[4] = {i + 1, i + w - 1, i + w, i + w + 1};
      const bool plain[4] = {!right || same(i, neighbour[kRight]),
                             !down || x == 0 || same(i, neighbour[kDownLeft]),
                             !down || same(i, neighbour[kDown]),
                             !down || !right || same(i, neighbour[kDownRight])};
      if (plain[kRight] && plain[kDownLeft] && plain[kDown] && plain[kDownRight]) continue;
      const Color c = mean(i);
      uint8_t bits = 0;
      for (const CentrePair k : {kRight, kDownLeft, kDown, kDownRight}) {
        const size_t j = neighbour[k];
        if (plain[k] || !count_[j]) continue;
        bits |= pairVerdicts(c, mean(j), threshold, signedColours) << (2 * k);
      }
      pairs[i] = bits;
    }
  });
  constexpr uint8_t kOwn = seenFromPixel(kRight) | seenFromPixel(kDownLeft) |
                           seenFromPixel(kDown) | seenFromPixel(kDownRight);
  tbb::parallel_for(0, height_, [&](int y) {
    auto gather = [&](int x) {
      const size_t i = index(x, y);
      bool edge = pairs[i] & kOwn;
      if (x > 0) edge |= pairs[i - 1] & seenFromNeighbour(kRight);
      if (y > 0) {
        const size_t up = i - static_cast<size_t>(width_);
        edge |= pairs[up] & seenFromNeighbour(kDown);
        if (x > 0) edge |= pairs[up - 1] & seenFromNeighbour(kDownRight);
        if (x + 1 < width_) edge |= pairs[up + 1] & seenFromNeighbour(kDownLeft);
      }
      edges[i] = edge;
    };
    if (y == 0 || width_ < 3) {
      for (int x = 0; x < width_; ++x) gather(x);
      return;
    }
    // Inside the frame every neighbour is there: the same bits without a
    // branch, many pixels to a vector instruction.
    // (__restrict: unsaid, the uint8_t stores might alias the rows read,
    // and GCC left the loop scalar.)
    gather(0);
    const uint8_t *__restrict row = &pairs[index(0, y)];
    const uint8_t *__restrict up = row - width_;
    uint8_t *__restrict out = &edges[index(0, y)];
    const int last = width_ - 1;
    for (int x = 1; x < last; ++x)
      out[x] = ((row[x] & kOwn) | (row[x - 1] & seenFromNeighbour(kRight)) |
                (up[x] & seenFromNeighbour(kDown)) | (up[x - 1] & seenFromNeighbour(kDownRight)) |
                (up[x + 1] & seenFromNeighbour(kDownLeft))) != 0;
    gather(width_ - 1);
  });
  return edges;
}

size_t SampleBuffer::updateActive(double threshold, uint32_t maxSamples) {
  // Not converged, then dilated by one pixel so the neighbours of a noisy
  // pixel (the other side of an edge, say) are not starved.
  if (wholeRegionActive_) return judgeRegion(threshold, maxSamples);
  // Only active pixels can be noisy: an inactive one had no noisy pixel
  // around it, so was not noisy itself, and took no samples since. So the
  // work is in proportion to the active pixels, not the frame. A verdict
  // reads only the pixel's and its neighbours' sums, so they are reached in
  // parallel. No pixel holds only its centre after the first verdicts.
  std::vector<uint8_t> verdicts(activeList_.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, activeList_.size(), 4096),
                    [&](const tbb::blocked_range<size_t> &r) {
                      setFlushToZero();
                      for (size_t k = r.begin(); k != r.end(); ++k)
                        verdicts[k] = isNoisy(activeList_[k], threshold, maxSamples, false);
                    });
  std::vector<uint32_t> noisy;
  for (size_t k = 0; k < activeList_.size(); ++k) {
    active_[activeList_[k]] = 0;
    if (verdicts[k]) noisy.push_back(activeList_[k]);
  }
  activeList_.clear();
  for (uint32_t i : noisy) {
    const int x = static_cast<int>(i % static_cast<uint32_t>(width_));
    const int y = static_cast<int>(i / static_cast<uint32_t>(width_));
    for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny)
      for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
        const size_t j = index(nx, ny);
        if (active_[j] || !inRegion(nx, ny) || count_[j] >= maxSamples) continue;
        active_[j] = 1;
        activeList_.push_back(static_cast<uint32_t>(j));
      }
  }
  return activeList_.size();
}

bool SampleBuffer::isNoisy(size_t i, double threshold, uint32_t maxSamples, bool edge) const {
  if (count_[i] >= maxSamples) return false;
  if (threshold <= 0) return true;
  return centreOnly_[i] ? edge : error(i) >= threshold;
}

void SampleBuffer::setActiveAround(const std::vector<uint8_t> &noisy, bool centres,
                                   uint32_t maxSamples) {
  // After Sobol samples any noisy neighbour keeps a pixel sampling (its
  // own samples may all have fallen on one side of an edge). After the
  // centre-first pass a pixel joins only where most of its neighbours are
  // noisy (at the frame's border, most of those it has): a straight edge
  // across a pixel always puts its centre and one of its neighbours' on
  // opposite sides (a half-plane that meets the pixel holds a corner of
  // the square of its neighbours' centres), so its own verdict catches
  // the edge, and the pixels along an edge need no ring around them.
  // Where most neighbours differ, the detail is finer than the centres
  // (distant checkers, a fine texture), and a centre that matches its
  // neighbours says little.
  const PixelWindow r = region_;
  // A pixel joins with more noisy neighbours than this, of eight.
  const int quietNeighbours = centres ? 4 : 0;
  tbb::parallel_for(r.y0, r.y1, [&](int y) {
    const uint8_t *row = &noisy[index(0, y)];
    const uint8_t *up = y > 0 ? row - width_ : nullptr;
    const uint8_t *down = y + 1 < height_ ? row + width_ : nullptr;
    const uint32_t *count = &count_[index(0, y)];
    uint8_t *active = &active_[index(0, y)];
    // A pixel at the frame's border: the neighbours it has.
    auto judgeBorder = [&](int x) {
      int neighbours = 0, noisyNeighbours = 0;
      for (const uint8_t *line : {up, row, down}) {
        if (!line) continue;
        for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
          if (line == row && nx == x) continue;
          ++neighbours;
          noisyNeighbours += line[nx];
        }
      }
      const bool joins = centres ? 2 * noisyNeighbours > neighbours : noisyNeighbours > 0;
      active[x] = count[x] < maxSamples && (row[x] || joins);
    };
    int x = r.x0;
    if (!up || !down) {
      for (; x < r.x1; ++x) judgeBorder(x);
      return;
    }
    if (x == 0) judgeBorder(x++);
    {
      // The rows apart, so that the loop is vectorised (judgeBorder's
      // lambda reads them through the pointers above).
      const uint8_t *__restrict u = up, *__restrict m = row, *__restrict d = down;
      const uint32_t *__restrict n = count;
      uint8_t *__restrict a = active;
      const uint32_t most = maxSamples;
      const int quiet = quietNeighbours;
      const int inner = std::min(r.x1, width_ - 1);
      for (int k = x; k < inner; ++k) {
        const int noisyNeighbours =
            u[k - 1] + u[k] + u[k + 1] + m[k - 1] + m[k + 1] + d[k - 1] + d[k] + d[k + 1];
        a[k] = (n[k] < most) & ((m[k] != 0) | (noisyNeighbours > quiet));
      }
      x = std::max(x, inner);
    }
    for (; x < r.x1; ++x) judgeBorder(x);
  });
}

size_t SampleBuffer::judgeRegion(double threshold, uint32_t maxSamples) {
  // The first verdicts are on every pixel of the region (after the
  // centre-first pass, one per pixel of the frame), so they and then their
  // neighbours' (setActiveAround) are taken pixel by pixel, by rows in
  // parallel, into flags for the frame; the list of active pixels is read
  // off the flags after.
  const size_t pixels = count_.size();
  const PixelWindow r = region_;
  bool centres = false;
  for (int y = r.y0; y < r.y1 && threshold > 0 && !centres; ++y) {
    const uint8_t *row = centreOnly_.data() + index(r.x0, y);
    centres = std::any_of(row, row + (r.x1 - r.x0), [](uint8_t c) { return c != 0; });
  }
  std::vector<uint8_t> noisy = centres ? centreEdges(threshold) : std::vector<uint8_t>(pixels);
  tbb::parallel_for(r.y0, r.y1, [&](int y) {
    setFlushToZero();
    const uint8_t *only = &centreOnly_[index(r.x0, y)];
    const int n = r.x1 - r.x0;
    if (centres && std::find(only, only + n, uint8_t{0}) == only + n) {
      // A row of centres only (the whole frame, after the centre-first
      // pass): the inlined verdict below, in a loop GCC vectorises.
      uint8_t *__restrict out = &noisy[index(r.x0, y)];
      const uint32_t *__restrict count = &count_[index(r.x0, y)];
      const uint32_t most = maxSamples;
      for (int k = 0; k < n; ++k) out[k] = (out[k] != 0) & (count[k] < most);
      return;
    }
    for (int x = r.x0; x < r.x1; ++x) {
      const size_t i = index(x, y);
      // isNoisy of a pixel of only its centre at a threshold above 0 (with
      // centres): its edge verdict, below maxSamples; inlined, as most of
      // such a frame is so.
      noisy[i] = centres && centreOnly_[i]
                     ? noisy[i] != 0 && count_[i] < maxSamples
                     : isNoisy(i, threshold, maxSamples, noisy[i] != 0);
    }
  });
  setActiveAround(noisy, centres, maxSamples);
  wholeRegionActive_ = false;
  // Read off eight flags at a time: most of a frame is inactive.
  for (int y = r.y0; y < r.y1; ++y) {
    const size_t row = index(0, y);
    int x = r.x0;
    for (; x + 8 <= r.x1; x += 8) {
      uint64_t flags;
      std::memcpy(&flags, &active_[row + x], sizeof flags);
      if (flags == 0) continue;
      for (int k = 0; k < 8; ++k)
        if (active_[row + x + k]) activeList_.push_back(static_cast<uint32_t>(row + x + k));
    }
    for (; x < r.x1; ++x)
      if (active_[row + x]) activeList_.push_back(static_cast<uint32_t>(row + x));
  }
  return activeList_.size();
}

namespace {

/// One row's share of the sampling report (summarizeSampling): its pixels'
/// samples, the most in one, and the error figures of those with two or
/// more.
struct SamplingRow {
  double errorSum = 0, errorMax = 0;
  size_t withError = 0;
  uint64_t samples = 0;
  uint32_t most = 0;
  void add(uint32_t n, float error) {
    samples += n;
    most = std::max(most, n);
    if (n < 2) return;
    errorSum += error;
    errorMax = std::max(errorMax, double(error));
    ++withError;
  }
};

/// The rows' figures summed in order into `r`: the same report whatever
/// the threads.
void reportRows(const std::vector<SamplingRow> &rows, SamplingReport &r) {
  SamplingRow all;
  for (const SamplingRow &row : rows) {
    all.errorSum += row.errorSum;
    all.errorMax = std::max(all.errorMax, row.errorMax);
    all.withError += row.withError;
    all.samples += row.samples;
    all.most = std::max(all.most, row.most);
  }
  r.samples = all.samples;
  r.maxPixelSamples = all.most;
  r.hasError = all.withError > 0;
  r.meanError = all.withError ? all.errorSum / static_cast<double>(all.withError) : 0;
  r.maxError = all.errorMax;
}

} // namespace

void SampleBuffer::writeTo(Film &film) const {
  // By rows in parallel: the film's pages are mapped as they are written.
  tbb::parallel_for(0, height_, [&](int y) {
    setFlushToZero();
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      const uint32_t n = count_[i];
      film.setSamples(x, y, n ? mean(i) : Color(), variance(i), n, samples_);
    }
  });
  summarizeSampling(film);
}

void SampleBuffer::moveTo(Film &film) && {
  // The sums become the means and the squares the estimates where they
  // lie: a pixel of one sample (a centre, whose squares were never
  // written) holds its mean and 0 estimate already, one without samples 0
  // (the same values writeTo gives), so only pixels of two samples or
  // more are written, and only in pages their samples mapped.
  // The report is summed here too (as summarizeSampling would from the
  // film): reading a refined pixel's estimate back would map its pages.
  static_assert(Film::kEstimateFloats <= kSquareFloats, "an estimate fits in a pixel's squares");
  std::vector<SamplingRow> rows(static_cast<size_t>(height_));
  tbb::parallel_for(0, height_, [&](int y) {
    setFlushToZero();
    SamplingRow &row = rows[static_cast<size_t>(y)];
    for (int x = 0; x < width_; ++x) {
      const size_t i = index(x, y);
      const uint32_t n = count_[i];
      assert(n >= 2 || n == 0 || centreOnly_[i]);
      if (n < 2) {
        row.add(n, 0.f);
        continue;
      }
      const Color m = mean(i);
      // A refined pixel's squares were never written: its pages stay
      // unmapped, and its estimate is their 0. (variance reads the sums.)
      float error = 0;
      if (!refined_[i]) {
        float *estimate = &squares_[i * kSquareFloats];
        Film::writeEstimate(estimate, m, variance(i), n, samples_);
        std::fill(estimate + Film::kEstimateFloats, estimate + kSquareFloats, 0.f);
        error = estimate[Film::kErrorFloat];
      }
      row.add(n, error);
      float *sum = &sums_[i * 3];
      sum[0] = static_cast<float>(m.r);
      sum[1] = static_cast<float>(m.g);
      sum[2] = static_cast<float>(m.b);
    }
  });
  film.adopt(std::move(sums_), std::move(count_), std::move(squares_), kSquareFloats);
  reportRows(rows, film.report);
}

void summarizeSampling(Film &film) {
  std::vector<SamplingRow> rows(static_cast<size_t>(film.height()));
  tbb::parallel_for(0, film.height(), [&](int y) {
    SamplingRow &row = rows[static_cast<size_t>(y)];
    for (int x = 0; x < film.width(); ++x) {
      const uint32_t n = film.sampleCount(x, y);
      row.add(n, n >= 2 ? film.error(x, y) : 0.f);
    }
  });
  reportRows(rows, film.report);
}

} // namespace lray
