// Pipeline: acceleration (kd-tree backend). The SAH build of KdTree:
// Wald & Havran 2006, "On building fast kd-trees for ray tracing, and on
// doing that in O(N log N)". Split candidates are the primitives' bound
// planes ("events"), sorted once per axis; each node sweeps its sorted lists
// to find the cheapest plane, then splits them into the children's lists in
// order, so only the events of primitives straddling the plane (re-clipped
// to each child: "perfect splits") need sorting again. Event positions are
// floats rounded outwards, so the float split planes the 8-byte nodes store
// classify exactly as the build did.
#include "accel/kdtree/kd_tree.h"

#include <tbb/concurrent_vector.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace lray {

namespace {

// Sweep order at one position: primitives ending there leave before planar
// ones are counted, which come before those starting there.
enum EventType : uint8_t { kEnd = 0, kPlanar = 1, kStart = 2 };

struct Event {
  float pos;
  uint32_t prim;
  uint8_t type;

  bool operator<(const Event &o) const { return pos < o.pos || (pos == o.pos && type < o.type); }
};

using EventList = std::vector<Event>;
using EventLists = std::array<EventList, 3>;

enum Side : uint8_t { kBoth = 0, kBelowOnly = 1, kAboveOnly = 2 };

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

// Usable bounds: non-empty and within float range (event positions are floats).
bool finiteBounds(const Bounds3 &b) {
  constexpr double kLimit = 1e38;
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(b.lo[a]) < kLimit && std::fabs(b.hi[a]) < kLimit && b.lo[a] <= b.hi[a]))
      return false; // also rejects NaN
  return true;
}

// Appends the events of one primitive with bounds b (already inside the node box).
void addEvents(EventLists &lists, uint32_t prim, const Bounds3 &b) {
  for (int a = 0; a < 3; ++a) {
    float lo = roundDown(b.lo[a]), hi = roundUp(b.hi[a]);
    if (lo == hi) {
      lists[a].push_back({lo, prim, kPlanar});
    } else {
      lists[a].push_back({lo, prim, kStart});
      lists[a].push_back({hi, prim, kEnd});
    }
  }
}

struct SplitChoice {
  int axis = -1;
  float pos = 0;
  bool planarBelow = true;
  double cost = std::numeric_limits<double>::infinity();
};

} // namespace

class KdTreeBuilder {
public:
  KdTreeBuilder(size_t primCount, const KdClipFunction &clip, const KdBuildOptions &options,
                int maxDepth)
      : clip_(clip), options_(options), maxDepth_(maxDepth),
        sides_([primCount] { return std::vector<uint8_t>(primCount, kBoth); }) {}

  KdTree run(EventLists events, size_t primCount, const Bounds3 &box) {
    KdTree tree;
    tree.bounds_ = box;
    nodes_.grow_by(1);
    buildNode(0, box, std::move(events), primCount, 0);

    tree.nodes_.assign(nodes_.begin(), nodes_.end());
    tree.primIndices_.assign(prims_.begin(), prims_.end());
    KdTreeInfo &info = tree.info_;
    info.nodes = tree.nodes_.size();
    info.depth = depthReached_.load();
    info.maxDepth = maxDepth_;
    info.primReferences = 0;
    for (const KdNode &n : tree.nodes_) {
      if (!n.isLeaf()) continue;
      ++info.leaves;
      if (n.primCount() == 0) ++info.emptyLeaves;
      info.primReferences += n.primCount();
    }
    return tree;
  }

private:
  // Sweeps one axis' sorted events for the cheapest plane strictly inside the box.
  SplitChoice sweepAxis(int a, const Bounds3 &box, const EventList &list, size_t n) const {
    SplitChoice best;
    if (!(box.hi[a] > box.lo[a])) return best;
    double invArea = 1.0 / box.surfaceArea();
    const SahCostModel &model = options_.cost;
    Vec3 d = box.diagonal();
    int b = (a + 1) % 3, c = (a + 2) % 3;
    // Child areas are linear in the split position: 2 (db dc + x (db + dc)).
    double capArea = 2 * d[b] * d[c], sideLength = 2 * (d[b] + d[c]);
    size_t nBelow = 0, nAbove = n;
    size_t i = 0;
    const size_t size = list.size();
    while (i < size) {
      float pos = list[i].pos;
      size_t ends = 0, planars = 0, starts = 0;
      while (i < size && list[i].pos == pos && list[i].type == kEnd) { ++ends; ++i; }
      while (i < size && list[i].pos == pos && list[i].type == kPlanar) { ++planars; ++i; }
      while (i < size && list[i].pos == pos && list[i].type == kStart) { ++starts; ++i; }
      nAbove -= planars + ends;
      if (pos > box.lo[a] && pos < box.hi[a]) {
        double pBelow = (capArea + (pos - box.lo[a]) * sideLength) * invArea;
        double pAbove = (capArea + (box.hi[a] - pos) * sideLength) * invArea;
        double costBelow = model.splitCost(pBelow, pAbove, nBelow + planars, nAbove);
        double costAbove = model.splitCost(pBelow, pAbove, nBelow, nAbove + planars);
        if (costBelow < best.cost) best = {a, pos, true, costBelow};
        if (costAbove < best.cost) best = {a, pos, false, costAbove};
      }
      nBelow += starts + planars;
    }
    return best;
  }

  // Big nodes do their per-axis passes in parallel. Isolated, so a waiting
  // thread cannot pick up another node's task, which would overwrite this
  // thread's side flags while this node still reads them.
  template <class PerAxis> void forEachAxis(size_t n, PerAxis &&perAxis) const {
    if (n >= 16 * options_.parallelThreshold) {
      tbb::this_task_arena::isolate([&] {
        tbb::parallel_invoke([&] { perAxis(0); }, [&] { perAxis(1); }, [&] { perAxis(2); });
      });
    } else {
      for (int a = 0; a < 3; ++a) perAxis(a);
    }
  }

  SplitChoice findSplit(const Bounds3 &box, const EventLists &events, size_t n) const {
    if (!(box.surfaceArea() > 0)) return {};
    SplitChoice perAxis[3];
    forEachAxis(n, [&](int a) { perAxis[a] = sweepAxis(a, box, events[a], n); });
    SplitChoice best = perAxis[0];
    for (int a = 1; a < 3; ++a)
      if (perAxis[a].cost < best.cost) best = perAxis[a];
    return best;
  }

  void makeLeaf(uint32_t nodeIndex, const EventList &axis0, size_t n) {
    if (n == 1) {
      for (const Event &e : axis0)
        if (e.type != kEnd) nodes_[nodeIndex] = KdNode::leaf(1, e.prim);
      return;
    }
    uint32_t offset = 0;
    if (n > 0) {
      auto it = prims_.grow_by(n);
      offset = static_cast<uint32_t>(it - prims_.begin());
      for (const Event &e : axis0)
        if (e.type != kEnd) *it++ = e.prim;
    }
    nodes_[nodeIndex] = KdNode::leaf(static_cast<uint32_t>(n), offset);
  }

  void buildNode(uint32_t nodeIndex, const Bounds3 &box, EventLists events, size_t n, int depth) {
    int reached = depthReached_.load(std::memory_order_relaxed);
    while (depth > reached && !depthReached_.compare_exchange_weak(reached, depth)) {
    }

    SplitChoice split;
    if (n > 0 && depth < maxDepth_) split = findSplit(box, events, n);
    if (split.axis < 0 || split.cost >= options_.cost.leafCost(n)) {
      makeLeaf(nodeIndex, events[0], n);
      releaseLists(events);
      return;
    }

    // Classify along the split axis in one pass: a primitive's start event
    // comes before its end event, so the end event can overrule the start's
    // tentative "both" and name the straddlers.
    const int axis = split.axis;
    const float s = split.pos;
    std::vector<uint8_t> &side = sides_.local();
    std::vector<uint32_t> straddling;
    for (const Event &e : events[axis]) {
      switch (e.type) {
      case kStart: side[e.prim] = e.pos >= s ? kAboveOnly : kBoth; break;
      case kEnd:
        if (e.pos <= s) side[e.prim] = kBelowOnly;
        else if (side[e.prim] == kBoth) straddling.push_back(e.prim);
        break;
      default:
        side[e.prim] = (e.pos < s || (e.pos == s && split.planarBelow)) ? kBelowOnly : kAboveOnly;
      }
    }

    Bounds3 boxBelow = box, boxAbove = box;
    boxBelow.hi[axis] = s;
    boxAbove.lo[axis] = s;

    // Straddling primitives are clipped to each child ("perfect splits");
    // their new events are sorted and merged into the one-sided primitives'
    // events, which stay sorted as they are copied.
    EventLists newBelow = takeLists(), newAbove = takeLists();
    for (uint32_t prim : straddling) {
      Bounds3 b = clip_(prim, boxBelow);
      if (finiteBounds(b)) addEvents(newBelow, prim, clampTo(b, boxBelow));
      b = clip_(prim, boxAbove);
      if (finiteBounds(b)) addEvents(newAbove, prim, clampTo(b, boxAbove));
    }
    EventLists below = takeLists(), above = takeLists();
    forEachAxis(n, [&](int a) {
      EventList &nb = newBelow[a], &na = newAbove[a];
      std::sort(nb.begin(), nb.end());
      std::sort(na.begin(), na.end());
      EventList &lb = below[a], &la = above[a];
      lb.reserve(events[a].size() + nb.size());
      la.reserve(events[a].size() + na.size());
      // Copy the one-sided events and merge the new ones in, in one pass.
      size_t ib = 0, ia = 0;
      for (const Event &e : events[a]) {
        uint8_t sd = side[e.prim];
        if (sd == kBelowOnly) {
          while (ib < nb.size() && nb[ib] < e) lb.push_back(nb[ib++]);
          lb.push_back(e);
        } else if (sd == kAboveOnly) {
          while (ia < na.size() && na[ia] < e) la.push_back(na[ia++]);
          la.push_back(e);
        }
      }
      lb.insert(lb.end(), nb.begin() + static_cast<std::ptrdiff_t>(ib), nb.end());
      la.insert(la.end(), na.begin() + static_cast<std::ptrdiff_t>(ia), na.end());
    });
    releaseLists(events);
    releaseLists(newBelow);
    releaseLists(newAbove);
    size_t nBelow = 0, nAbove = 0;
    for (const Event &e : below[0]) nBelow += e.type != kEnd;
    for (const Event &e : above[0]) nAbove += e.type != kEnd;

    auto it = nodes_.grow_by(2);
    size_t childIndex = static_cast<size_t>(it - nodes_.begin());
    if (childIndex + 1 > KdNode::kMaxIndex) {
      std::fprintf(stderr, "lray: kd-tree exceeds %u nodes\n", KdNode::kMaxIndex);
      std::abort();
    }
    uint32_t child = static_cast<uint32_t>(childIndex);
    nodes_[nodeIndex] = KdNode::interior(axis, s, child);

    if (n >= options_.parallelThreshold) {
      tbb::task_group group;
      group.run([&, child, nBelow, depth] {
        buildNode(child, boxBelow, std::move(below), nBelow, depth + 1);
      });
      buildNode(child + 1, boxAbove, std::move(above), nAbove, depth + 1);
      group.wait();
    } else {
      buildNode(child, boxBelow, std::move(below), nBelow, depth + 1);
      buildNode(child + 1, boxAbove, std::move(above), nAbove, depth + 1);
    }
  }

  // Event lists of small nodes are recycled through a per-thread pool: the
  // millions of deep nodes would otherwise each pay a dozen mallocs.
  static constexpr size_t kPooledCapacity = 1 << 12;
  static constexpr size_t kPoolSize = 1024;
  EventLists takeLists() {
    EventLists lists;
    std::vector<EventList> &pool = pools_.local();
    for (EventList &l : lists) {
      if (pool.empty()) break;
      l = std::move(pool.back());
      pool.pop_back();
    }
    return lists;
  }
  void releaseLists(EventLists &lists) {
    std::vector<EventList> &pool = pools_.local();
    for (EventList &l : lists) {
      if (l.capacity() > 0 && l.capacity() <= kPooledCapacity && pool.size() < kPoolSize) {
        l.clear();
        pool.push_back(std::move(l));
      }
      EventList().swap(l);
    }
  }

  static Bounds3 clampTo(const Bounds3 &b, const Bounds3 &box) {
    Bounds3 r;
    r.lo = max(b.lo, box.lo);
    r.hi = min(b.hi, box.hi);
    // Rounding in the clipper may leave a sliver just outside: keep it as a plane.
    for (int a = 0; a < 3; ++a)
      if (r.lo[a] > r.hi[a]) r.lo[a] = r.hi[a] = std::clamp(b.lo[a], box.lo[a], box.hi[a]);
    return r;
  }

  const KdClipFunction &clip_;
  const KdBuildOptions &options_;
  int maxDepth_;
  // Per-thread side flags indexed by primitive: a node classifies and splits
  // its lists without yielding, so one array per thread is never shared.
  tbb::enumerable_thread_specific<std::vector<uint8_t>> sides_;
  tbb::enumerable_thread_specific<std::vector<EventList>> pools_;
  tbb::concurrent_vector<KdNode> nodes_;
  tbb::concurrent_vector<uint32_t> prims_;
  std::atomic<int> depthReached_{0};
};

KdTree KdTree::build(std::span<const Bounds3> primBounds, const KdClipFunction &clip,
                     const KdBuildOptions &options) {
  assert(primBounds.size() <= KdNode::kMaxIndex);
  EventLists events;
  Bounds3 box;
  size_t n = 0;
  for (const Bounds3 &b : primBounds)
    if (finiteBounds(b)) ++n;
  if (n == 0) return {};
  for (EventList &list : events) list.reserve(2 * n);
  for (size_t i = 0; i < primBounds.size(); ++i) {
    const Bounds3 &b = primBounds[i];
    if (!finiteBounds(b)) continue;
    addEvents(events, static_cast<uint32_t>(i), b);
    box.extend(Vec3(roundDown(b.lo.x), roundDown(b.lo.y), roundDown(b.lo.z)));
    box.extend(Vec3(roundUp(b.hi.x), roundUp(b.hi.y), roundUp(b.hi.z)));
  }
  tbb::parallel_invoke([&] { std::sort(events[0].begin(), events[0].end()); },
                       [&] { std::sort(events[1].begin(), events[1].end()); },
                       [&] { std::sort(events[2].begin(), events[2].end()); });

  int maxDepth = options.maxDepth;
  if (maxDepth <= 0)
    maxDepth = static_cast<int>(std::lround(8 + 1.3 * std::log2(static_cast<double>(n))));
  maxDepth = std::min(maxDepth, kMaxDepth);

  KdTreeBuilder builder(primBounds.size(), clip, options, maxDepth);
  return builder.run(std::move(events), n, box);
}

} // namespace lray
