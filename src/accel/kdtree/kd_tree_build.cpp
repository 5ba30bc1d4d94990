// Pipeline: acceleration (kd-tree backend). The SAH build of KdTree, in two
// regimes. Large nodes choose their plane by binning (Wald 2007, "On fast
// construction of SAH-based bounding volume hierarchies"; Shevtsov, Soupikov
// & Kapustin 2007 for kd-trees): primitive bounds are counted into a fixed
// number of bins per axis, in parallel, and the SAH is evaluated at the bin
// boundaries plus the two planes that cut off the empty space exactly. Small
// nodes evaluate every candidate plane exactly: the events (primitive bound
// planes) are sorted and swept as in Wald & Havran 2006, "On building fast
// kd-trees for ray tracing, and on doing that in O(N log N)". Primitives
// straddling a chosen plane are clipped to each child ("perfect splits").
// Bounds and planes are floats rounded outwards, so the float split planes
// the 8-byte nodes store classify exactly as the build did.
#include "accel/kdtree/kd_tree.h"

#include <tbb/concurrent_vector.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace lray {

namespace {

// Nodes with more primitives than this choose their plane by binning.
constexpr size_t kExactLimit = 16;
// Bins per axis for large nodes.
constexpr int kBins = 64;
// Nodes at least this large bin and partition their primitives in parallel.
constexpr size_t kParallelPassLimit = size_t{1} << 16;
constexpr size_t kParallelChunks = 32;

/// One primitive's bounds clipped to the current node's box, in floats
/// rounded outwards.
struct PrimRef {
  float lo[3], hi[3];
  uint32_t prim;
};

float roundDown(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

float roundUp(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// Usable bounds: non-empty and within float range (planes are floats).
bool finiteBounds(const Bounds3 &b) {
  constexpr double kLimit = 1e38;
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(b.lo[a]) < kLimit && std::fabs(b.hi[a]) < kLimit && b.lo[a] <= b.hi[a]))
      return false; // also rejects NaN
  return true;
}

PrimRef makeRef(uint32_t prim, const Bounds3 &b) {
  PrimRef r;
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = roundDown(b.lo[a]);
    r.hi[a] = roundUp(b.hi[a]);
  }
  r.prim = prim;
  return r;
}

Bounds3 clampTo(const Bounds3 &b, const Bounds3 &box) {
  Bounds3 r;
  r.lo = max(b.lo, box.lo);
  r.hi = min(b.hi, box.hi);
  // Rounding in the clipper may leave a sliver just outside: keep it as a plane.
  for (int a = 0; a < 3; ++a)
    if (r.lo[a] > r.hi[a]) r.lo[a] = r.hi[a] = std::clamp(b.lo[a], box.lo[a], box.hi[a]);
  return r;
}

struct SplitChoice {
  int axis = -1;
  float pos = 0;
  bool planarBelow = true;
  double cost = std::numeric_limits<double>::infinity();

  void consider(int a, float p, bool below, double c) {
    if (c < cost) *this = {a, p, below, c};
  }
};

// Surface-area ratios of the two children of a split along one axis: the
// child areas are linear in the split position, 2 (db dc + x (db + dc)).
struct AxisAreas {
  double lo, hi, capArea, sideLength, invArea;

  AxisAreas(const Bounds3 &box, int a) : lo(box.lo[a]), hi(box.hi[a]) {
    Vec3 d = box.diagonal();
    int b = (a + 1) % 3, c = (a + 2) % 3;
    capArea = 2 * d[b] * d[c];
    sideLength = 2 * (d[b] + d[c]);
    invArea = 1.0 / box.surfaceArea();
  }
  double below(double pos) const { return (capArea + (pos - lo) * sideLength) * invArea; }
  double above(double pos) const { return (capArea + (hi - pos) * sideLength) * invArea; }
};

// Sweep order at one position: primitives ending there leave before planar
// ones are counted, which come before those starting there.
enum EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// An event as one integer that sorts like (position, type): the float's
// bits mapped to an unsigned order, then the type.
uint64_t eventKey(float pos, EventType type) {
  uint32_t bits = std::bit_cast<uint32_t>(pos + 0.0f); // -0 becomes +0
  bits = (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
  return (uint64_t{bits} << 2) | type;
}

float eventPos(uint64_t key) {
  uint32_t bits = static_cast<uint32_t>(key >> 2);
  bits = (bits & 0x80000000u) ? bits & 0x7fffffffu : ~bits;
  return std::bit_cast<float>(bits);
}

// Per-axis counts of primitive starts and ends in each bin, and the
// primitives' extent (for the exact empty-space planes).
struct Bins {
  uint32_t start[3][kBins] = {};
  uint32_t end[3][kBins] = {};
  float minLo[3], maxHi[3];

  Bins() {
    for (int a = 0; a < 3; ++a) {
      minLo[a] = std::numeric_limits<float>::infinity();
      maxHi[a] = -std::numeric_limits<float>::infinity();
    }
  }
  void add(const Bins &o) {
    for (int a = 0; a < 3; ++a) {
      for (int k = 0; k < kBins; ++k) {
        start[a][k] += o.start[a][k];
        end[a][k] += o.end[a][k];
      }
      minLo[a] = std::min(minLo[a], o.minLo[a]);
      maxHi[a] = std::max(maxHi[a], o.maxHi[a]);
    }
  }
};

// Side of a primitive relative to the plane (see SplitChoice).
enum Side { kBelowOnly, kAboveOnly, kBoth };

Side classify(const PrimRef &r, int axis, float s, bool planarBelow) {
  float lo = r.lo[axis], hi = r.hi[axis];
  if (lo == s && hi == s) return planarBelow ? kBelowOnly : kAboveOnly;
  if (hi <= s) return kBelowOnly;
  if (lo >= s) return kAboveOnly;
  return kBoth;
}

} // namespace

class KdTreeBuilder {
public:
  KdTreeBuilder(const KdClipFunction &clip, const KdBuildOptions &options, int maxDepth)
      : clip_(clip), options_(options), maxDepth_(maxDepth) {}

  KdTree run(std::vector<PrimRef> refs, const Bounds3 &box) {
    KdTree tree;
    tree.bounds_ = box;
    nodes_.grow_by(1);
    buildLarge(0, box, std::move(refs), 0);

    tree.nodes_.assign(nodes_.begin(), nodes_.end());
    tree.primIndices_.assign(prims_.begin(), prims_.end());
    KdTreeInfo &info = tree.info_;
    info.nodes = tree.nodes_.size();
    info.depth = depthReached_.load();
    info.maxDepth = maxDepth_;
    info.primReferences = 0;
    info.paddedReferences = tree.primIndices_.size();
    for (const KdNode &n : tree.nodes_) {
      if (!n.isLeaf()) continue;
      ++info.leaves;
      if (n.primCount() == 0) ++info.emptyLeaves;
      info.primReferences += n.primCount();
    }
    return tree;
  }

private:
  // Working memory of one thread's serial subtree: node lists are stacked in
  // `refs` (children appended after their parent, dropped when done), so the
  // many small nodes allocate nothing.
  struct Scratch {
    std::vector<PrimRef> refs;
    std::vector<uint64_t> keys;
  };

  // ---- Choosing the plane ----

  SplitChoice chooseSplit(const Bounds3 &box, const PrimRef *refs, size_t n,
                          std::vector<uint64_t> &keys) const {
    if (!(box.surfaceArea() > 0)) return {};
    // No split can cost less than one traversal step (times the empty-space
    // factor): small enough nodes are leaves without looking.
    const SahCostModel &model = options_.cost;
    if (model.leafCost(n) <= model.traversalCost * std::min(1.0, model.emptySpaceFactor)) return {};
    return n <= kExactLimit ? exactSplit(box, refs, n, keys) : binnedSplit(box, refs, n);
  }

  // Every candidate plane: sort each axis' events and sweep them.
  SplitChoice exactSplit(const Bounds3 &box, const PrimRef *refs, size_t n,
                         std::vector<uint64_t> &keys) const {
    SplitChoice best;
    const SahCostModel &model = options_.cost;
    for (int a = 0; a < 3; ++a) {
      if (!(box.hi[a] > box.lo[a])) continue;
      keys.clear();
      for (size_t i = 0; i < n; ++i) {
        float lo = refs[i].lo[a], hi = refs[i].hi[a];
        if (lo == hi) {
          keys.push_back(eventKey(lo, kPlanar));
        } else {
          keys.push_back(eventKey(lo, kStart));
          keys.push_back(eventKey(hi, kEnd));
        }
      }
      std::sort(keys.begin(), keys.end());
      AxisAreas areas(box, a);
      size_t nBelow = 0, nAbove = n;
      size_t i = 0;
      const size_t size = keys.size();
      while (i < size) {
        const uint64_t posBits = keys[i] >> 2;
        size_t counts[3] = {0, 0, 0};
        for (; i < size && keys[i] >> 2 == posBits; ++i) ++counts[keys[i] & 3];
        const size_t ends = counts[kEnd], planars = counts[kPlanar], starts = counts[kStart];
        nAbove -= planars + ends;
        const float pos = eventPos(keys[i - 1]);
        if (pos > areas.lo && pos < areas.hi) {
          double pBelow = areas.below(pos), pAbove = areas.above(pos);
          best.consider(a, pos, true, model.splitCost(pBelow, pAbove, nBelow + planars, nAbove));
          best.consider(a, pos, false, model.splitCost(pBelow, pAbove, nBelow, nAbove + planars));
        }
        nBelow += starts + planars;
      }
    }
    return best;
  }

  static constexpr float kLastBin = kBins - 1;

  static void binRange(const Bounds3 &box, const float scale[3], const PrimRef *refs, size_t n,
                       Bins &bins) {
    const float boxLo[3] = {static_cast<float>(box.lo.x), static_cast<float>(box.lo.y),
                            static_cast<float>(box.lo.z)};
    for (size_t i = 0; i < n; ++i) {
      const PrimRef &r = refs[i];
      for (int a = 0; a < 3; ++a) {
        // Clamped as floats: the conversion to int is only defined in range.
        float fLo = std::clamp((r.lo[a] - boxLo[a]) * scale[a], 0.0f, kLastBin);
        float fHi = std::clamp((r.hi[a] - boxLo[a]) * scale[a], 0.0f, kLastBin);
        ++bins.start[a][static_cast<int>(fLo)];
        ++bins.end[a][static_cast<int>(fHi)];
        bins.minLo[a] = std::min(bins.minLo[a], r.lo[a]);
        bins.maxHi[a] = std::max(bins.maxHi[a], r.hi[a]);
      }
    }
  }

  // Candidate planes at the bin boundaries (counts approximate near a
  // boundary: only the cost estimate suffers, never correctness) and at the
  // primitives' extent, where cutting off empty space is exact.
  SplitChoice binnedSplit(const Bounds3 &box, const PrimRef *refs, size_t n) const {
    float scale[3];
    for (int a = 0; a < 3; ++a) {
      double extent = box.hi[a] - box.lo[a];
      scale[a] = extent > 0 ? static_cast<float>(kBins / extent) : 0.0f;
      if (!std::isfinite(scale[a])) scale[a] = 0; // a sliver of a box: one bin
    }
    Bins bins;
    if (n >= kParallelPassLimit) {
      std::array<Bins, kParallelChunks> partial;
      tbb::parallel_for(size_t{0}, kParallelChunks, [&](size_t c) {
        size_t first = n * c / kParallelChunks, last = n * (c + 1) / kParallelChunks;
        binRange(box, scale, refs + first, last - first, partial[c]);
      });
      for (const Bins &p : partial) bins.add(p);
    } else {
      binRange(box, scale, refs, n, bins);
    }

    SplitChoice best;
    const SahCostModel &model = options_.cost;
    for (int a = 0; a < 3; ++a) {
      if (!(box.hi[a] > box.lo[a])) continue;
      AxisAreas areas(box, a);
      const double width = (box.hi[a] - box.lo[a]) / kBins;
      size_t nBelow = 0, nAbove = n;
      for (int k = 1; k < kBins; ++k) {
        nBelow += bins.start[a][k - 1];
        nAbove -= bins.end[a][k - 1];
        float pos = static_cast<float>(box.lo[a] + k * width);
        if (!(pos > areas.lo && pos < areas.hi)) continue;
        best.consider(a, pos, true,
                      model.splitCost(areas.below(pos), areas.above(pos), nBelow, nAbove));
      }
      // Everything at or above minLo, at or below maxHi: one child empty.
      float lo = bins.minLo[a], hi = bins.maxHi[a];
      if (lo > areas.lo && lo < areas.hi)
        best.consider(a, lo, false, model.splitCost(areas.below(lo), areas.above(lo), 0, n));
      if (hi > areas.lo && hi < areas.hi)
        best.consider(a, hi, true, model.splitCost(areas.below(hi), areas.above(hi), n, 0));
    }
    return best;
  }

  // ---- Splitting the lists ----

  // The part of a straddling primitive inside a child box ("perfect split").
  bool clipRef(uint32_t prim, const Bounds3 &childBox, PrimRef &out) const {
    Bounds3 b = clip_(prim, childBox);
    if (!finiteBounds(b)) return false;
    out = makeRef(prim, clampTo(b, childBox));
    return true;
  }

  // Appends the references of one child (below or above) to `out`.
  template <class Out>
  void appendSide(const PrimRef *refs, size_t n, const SplitChoice &split, bool below,
                  const Bounds3 &childBox, Out &out) const {
    const Side keep = below ? kBelowOnly : kAboveOnly;
    for (size_t i = 0; i < n; ++i) {
      Side side = classify(refs[i], split.axis, split.pos, split.planarBelow);
      if (side == keep) {
        out.push_back(refs[i]);
      } else if (side == kBoth) {
        PrimRef clipped;
        if (clipRef(refs[i].prim, childBox, clipped)) out.push_back(clipped);
      }
    }
  }

  // ---- Nodes ----

  void noteDepth(int depth) {
    int reached = depthReached_.load(std::memory_order_relaxed);
    while (depth > reached && !depthReached_.compare_exchange_weak(reached, depth)) {
    }
  }

  void makeLeaf(uint32_t nodeIndex, const PrimRef *refs, size_t n) {
    uint32_t offset = 0;
    if (n > 0) {
      // Whole aligned blocks: every leaf then starts on a multiple too.
      const size_t align = options_.leafAlignment;
      const size_t padded = (n + align - 1) / align * align;
      auto it = prims_.grow_by(padded);
      offset = static_cast<uint32_t>(it - prims_.begin());
      for (size_t i = 0; i < padded; ++i) *it++ = refs[std::min(i, n - 1)].prim;
    }
    nodes_[nodeIndex] = KdNode::leaf(static_cast<uint32_t>(n), offset);
  }

  uint32_t makeInterior(uint32_t nodeIndex, const SplitChoice &split) {
    auto it = nodes_.grow_by(2);
    size_t childIndex = static_cast<size_t>(it - nodes_.begin());
    if (childIndex + 1 > KdNode::kMaxIndex) {
      std::fprintf(stderr, "lray: kd-tree exceeds %u nodes\n", KdNode::kMaxIndex);
      std::abort();
    }
    uint32_t child = static_cast<uint32_t>(childIndex);
    nodes_[nodeIndex] = KdNode::interior(split.axis, split.pos, child);
    return child;
  }

  bool worthSplitting(const SplitChoice &split, size_t n) const {
    return split.axis >= 0 && split.cost < options_.cost.leafCost(n);
  }

  static void childBoxes(const Bounds3 &box, const SplitChoice &split, Bounds3 &below,
                         Bounds3 &above) {
    below = box;
    above = box;
    below.hi[split.axis] = split.pos;
    above.lo[split.axis] = split.pos;
  }

  // Nodes above the parallel threshold: own lists, children built as tasks.
  void buildLarge(uint32_t nodeIndex, const Bounds3 &box, std::vector<PrimRef> refs, int depth) {
    const size_t n = refs.size();
    if (n < options_.parallelThreshold) {
      Scratch scratch;
      scratch.refs.reserve(4 * n + 64);
      scratch.refs.assign(refs.begin(), refs.end());
      std::vector<PrimRef>().swap(refs);
      buildSerial(nodeIndex, box, scratch, 0, n, depth);
      return;
    }
    noteDepth(depth);
    SplitChoice split;
    std::vector<uint64_t> keys;
    if (depth < maxDepth_) split = chooseSplit(box, refs.data(), n, keys);
    if (!worthSplitting(split, n)) {
      makeLeaf(nodeIndex, refs.data(), n);
      return;
    }
    Bounds3 boxBelow, boxAbove;
    childBoxes(box, split, boxBelow, boxAbove);
    std::vector<PrimRef> below, above;
    if (n >= kParallelPassLimit) {
      // Chunks split side by side, then concatenated in order.
      std::array<std::vector<PrimRef>, kParallelChunks> partBelow, partAbove;
      tbb::parallel_for(size_t{0}, 2 * kParallelChunks, [&](size_t job) {
        size_t c = job / 2;
        size_t first = n * c / kParallelChunks, last = n * (c + 1) / kParallelChunks;
        if (job % 2 == 0)
          appendSide(refs.data() + first, last - first, split, true, boxBelow, partBelow[c]);
        else
          appendSide(refs.data() + first, last - first, split, false, boxAbove, partAbove[c]);
      });
      size_t nb = 0, na = 0;
      for (size_t c = 0; c < kParallelChunks; ++c) {
        nb += partBelow[c].size();
        na += partAbove[c].size();
      }
      below.reserve(nb);
      above.reserve(na);
      for (size_t c = 0; c < kParallelChunks; ++c) {
        below.insert(below.end(), partBelow[c].begin(), partBelow[c].end());
        above.insert(above.end(), partAbove[c].begin(), partAbove[c].end());
      }
    } else {
      appendSide(refs.data(), n, split, true, boxBelow, below);
      appendSide(refs.data(), n, split, false, boxAbove, above);
    }
    std::vector<PrimRef>().swap(refs);

    uint32_t child = makeInterior(nodeIndex, split);
    tbb::task_group group;
    group.run([&, child, depth] { buildLarge(child, boxBelow, std::move(below), depth + 1); });
    buildLarge(child + 1, boxAbove, std::move(above), depth + 1);
    group.wait();
  }

  // The node's list is scratch.refs[begin, end); children are appended
  // after the current end of scratch.refs, which is restored on return.
  void buildSerial(uint32_t nodeIndex, const Bounds3 &box, Scratch &scratch, size_t begin,
                   size_t end, int depth) {
    noteDepth(depth);
    const size_t n = end - begin;
    SplitChoice split;
    if (n > 0 && depth < maxDepth_)
      split = chooseSplit(box, scratch.refs.data() + begin, n, scratch.keys);
    if (!worthSplitting(split, n)) {
      makeLeaf(nodeIndex, scratch.refs.data() + begin, n);
      return;
    }
    Bounds3 boxBelow, boxAbove;
    childBoxes(box, split, boxBelow, boxAbove);

    std::vector<PrimRef> &refs = scratch.refs;
    const size_t mark = refs.size();
    // Room for both children (each at most n), so the node's own list stays
    // put while they are appended.
    if (refs.capacity() < mark + 2 * n) refs.reserve(std::max(mark + 2 * n, 2 * refs.capacity()));
    appendSide(refs.data() + begin, n, split, true, boxBelow, refs);
    const size_t mid = refs.size();
    appendSide(refs.data() + begin, n, split, false, boxAbove, refs);
    const size_t last = refs.size();

    uint32_t child = makeInterior(nodeIndex, split);
    buildSerial(child, boxBelow, scratch, mark, mid, depth + 1);
    buildSerial(child + 1, boxAbove, scratch, mid, last, depth + 1);
    refs.resize(mark);
  }

  const KdClipFunction &clip_;
  const KdBuildOptions &options_;
  int maxDepth_;
  tbb::concurrent_vector<KdNode> nodes_;
  tbb::concurrent_vector<uint32_t> prims_;
  std::atomic<int> depthReached_{0};
};

KdTree KdTree::build(std::span<const Bounds3> primBounds, const KdClipFunction &clip,
                     const KdBuildOptions &options) {
  assert(primBounds.size() <= KdNode::kMaxIndex);
  assert(options.leafAlignment > 0 && std::has_single_bit(options.leafAlignment));
  std::vector<PrimRef> refs;
  Bounds3 box;
  size_t n = 0;
  for (const Bounds3 &b : primBounds)
    if (finiteBounds(b)) ++n;
  if (n == 0) return {};
  refs.reserve(n);
  for (size_t i = 0; i < primBounds.size(); ++i) {
    const Bounds3 &b = primBounds[i];
    if (!finiteBounds(b)) continue;
    PrimRef r = makeRef(static_cast<uint32_t>(i), b);
    box.extend(Vec3(r.lo[0], r.lo[1], r.lo[2]));
    box.extend(Vec3(r.hi[0], r.hi[1], r.hi[2]));
    refs.push_back(r);
  }

  int maxDepth = options.maxDepth;
  if (maxDepth <= 0)
    maxDepth = static_cast<int>(std::lround(8 + 1.3 * std::log2(static_cast<double>(n))));
  maxDepth = std::min(maxDepth, kMaxDepth);

  KdTreeBuilder builder(clip, options, maxDepth);
  return builder.run(std::move(refs), box);
}

} // namespace lray
