// Pipeline: acceleration (kd-tree backend). Builds the two-level kd-tree and
// answers closest-hit and any-hit queries; mesh rays are moved into object
// space (direction not normalised, so t is the same in both spaces).
#include "accel/kdtree/kdtree_accelerator.h"

#include "accel/kdtree/triangle_clip.h"
#include "accel/kdtree/watertight_triangle.h"
#include "geometry/float_frame.h"
#include "geometry/shape.h"
#include "util/cpu_features.h"

#include <tbb/parallel_for.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>
#include <type_traits>
#include <unordered_map>

namespace lray {

namespace {

struct TriangleCorners {
  Vec3 p0, p1, p2;
};

TriangleCorners corners(const MeshData &mesh, uint32_t triangle) {
  const uint32_t *idx = mesh.triangleIndices.data() + 3 * size_t{triangle};
  return {toVec3(mesh.positions[idx[0]]), toVec3(mesh.positions[idx[1]]),
          toVec3(mesh.positions[idx[2]])};
}

/// Whether the ray starts outside `box` on some axis and does not move
/// towards it along that axis: from t = 0 on (its tMin is not negative) it
/// stays on that side, so it meets nothing inside. Exact (comparisons
/// only); a NaN compares false and leaves the ray to the tests.
[[gnu::always_inline]] inline bool movesAwayFrom(const Ray &ray, const Bounds3 &box) {
  if (!(ray.tMin >= 0)) return false;
  bool away = false;
  for (int k = 0; k < 3; ++k)
    away |= (ray.o[k] > box.hi[k] && ray.d[k] >= 0) | (ray.o[k] < box.lo[k] && ray.d[k] <= 0);
  return away;
}

// Calls f(std::integral_constant<int, kz>) for the ray's dominant axis kz,
// so the triangle test of a whole traversal is compiled for that axis.
template <class F> [[gnu::always_inline]] inline bool withRayAxis(int kz, F &&f) {
  switch (kz) {
  case 0: return f(std::integral_constant<int, 0>{});
  case 1: return f(std::integral_constant<int, 1>{});
  default: return f(std::integral_constant<int, 2>{});
  }
}

// The entities a ray has just been tested against. An entity overlapping
// several top-level leaves is met once in each, but its test already
// covered the whole ray up to the nearest hit: a second one cannot find a
// nearer hit (or, for occlusion, any hit).
class Mailbox {
public:
  /// False when `prim` is among the last four tested; records it otherwise.
  bool firstVisit(uint32_t prim) {
    for (uint32_t p : recent_)
      if (p == prim) return false;
    recent_[next_++ % 4] = prim;
    return true;
  }

private:
  uint32_t recent_[4] = {~0u, ~0u, ~0u, ~0u};
  uint32_t next_ = 0;
};

// Mailbox for the lanes of a packet together: the last four entities
// tested, each with the lanes it was tested for.
class PacketMailbox {
public:
  /// The lanes of `lanes` that have not just tested `prim`; records them.
  uint32_t firstVisits(uint32_t prim, uint32_t lanes) {
    for (int k = 0; k < 4; ++k)
      if (recent_[k] == prim) {
        lanes &= ~tested_[k];
        tested_[k] |= lanes;
        return lanes;
      }
    recent_[next_ % 4] = prim;
    tested_[next_++ % 4] = lanes;
    return lanes;
  }

private:
  uint32_t recent_[4] = {~0u, ~0u, ~0u, ~0u};
  uint32_t tested_[4] = {};
  uint32_t next_ = 0;
};

// Leaves of at most this many triangles skip the prefilter (two exact
// tests cost less than a packet test and the prefilter ray's setup).
constexpr uint32_t kDirectTestLimit = 2;

// Packets pay in large trees, whose steps miss the caches: on the bumpy
// sphere at 1280x960 (one thread) they shortened the frames of 10^4 and
// 10^6 triangles but lengthened those of 10^2, a tree of 15 nodes
// (bench/HISTORY.md, figures from source comments). Scenes whose trees all
// have fewer nodes trace single rays, and in a packet's scene such a mesh
// takes its lanes one by one.
constexpr size_t kPacketMinNodes = 4096;

// A mesh whose vertices move: each triangle by its bounds over the shutter
// (its corners at every step), clipped to a node as a box.
KdTree buildMovingMeshTree(const MeshMotion &motion) {
  const size_t n = motion.steps[0]->triangleIndices.size() / 3;
  std::vector<Bounds3> bounds(n);
  tbb::parallel_for(size_t{0}, n,
                    [&](size_t i) { bounds[i] = motion.triangleBounds(static_cast<uint32_t>(i)); });
  return KdTree::build(bounds, [&bounds](uint32_t i, const Bounds3 &box) {
    Bounds3 b = bounds[i];
    b.lo = max(b.lo, box.lo);
    b.hi = min(b.hi, box.hi);
    return b;
  });
}

KdTree buildMeshTree(const MeshData &mesh) {
  size_t n = mesh.triangleIndices.size() / 3;
  std::vector<Bounds3> bounds(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    TriangleCorners c = corners(mesh, static_cast<uint32_t>(i));
    Bounds3 b(c.p0, c.p1);
    b.extend(c.p2);
    bounds[i] = b;
  });
  // Triangle trees stop splitting earlier than the model's defaults, and
  // earlier still as the tree outgrows the caches (a step down costs more).
  // With the float prefilter (eight leaf triangles per AVX2 test)
  // bench_kd_rays on the bumpy sphere was fastest at traversal cost 120
  // on small meshes (100 triangles; both 60 and 240 were slower) and 240 on
  // large ones (1M triangles: also fewer nodes and less memory; the depth
  // limit and empty-space factor did nothing). With the start-side descent
  // the switch moved from 2^18 down to 2^15 triangles: 240 was faster for
  // incoherent rays at 10^5 and no slower at 10^4 (bench/HISTORY.md,
  // figures from source comments).
  KdBuildOptions options;
  options.leafAlignment = kPacketLanes;
  options.cost.traversalCost = n < (size_t{1} << 15) ? 120 : 240;
  return KdTree::build(
      bounds,
      [&mesh](uint32_t i, const Bounds3 &box) {
        TriangleCorners c = corners(mesh, i);
        return clipTriangleToBox(c.p0, c.p1, c.p2, box);
      },
      options);
}

} // namespace

KdTreeAccelerator::KdTreeAccelerator(const Scene &scene)
    : scene_(scene), frameOrigin_(floatFrameOrigin(scene)), useAvx2_(cpuHasAvx2()),
      unbounded_(scene), moving_(scene) {
  auto start = std::chrono::steady_clock::now();

  // One bottom-level tree per distinct MeshData (shared_ptr identity).
  std::unordered_map<const MeshData *, uint32_t> treeOfMesh;
  std::vector<Bounds3> topBounds;
  for (uint32_t i = 0; i < scene.entities.size(); ++i) {
    const Entity &e = scene.entities[i];
    Instance inst;
    inst.entity = i;
    if (e.isMesh()) {
      if (!e.mesh || e.mesh->triangleIndices.empty()) continue;
      if (e.vertexMotion) {
        // Its own tree: no other entity's triangles move the same way.
        inst.meshTree = static_cast<uint32_t>(meshTrees_.size());
        meshTrees_.push_back({e.mesh.get(), e.vertexMotion.get(), KdTree()});
      } else {
        auto [it, added] =
            treeOfMesh.try_emplace(e.mesh.get(), static_cast<uint32_t>(meshTrees_.size()));
        if (added) meshTrees_.push_back({e.mesh.get(), nullptr, KdTree()});
        inst.meshTree = it->second;
      }
      if (e.motion) {
        inst.transform = kMoving; // each ray meets it where it is at the ray's time
      } else if (!e.worldFromObject.isIdentity()) {
        inst.transform = static_cast<uint32_t>(transforms_.size());
        transforms_.push_back(e.worldFromObject.inverse());
      }
      // A moving mesh: its bounds over the whole shutter.
      topBounds.push_back(e.moves()
                              ? meshWorldBounds(e)
                              : transformedBounds(meshObjectBounds(*e.mesh), e.worldFromObject));
      ++stats_.instances;
    } else {
      ++stats_.primitives;
      if (UnboundedShapes::holds(e)) continue;
      topBounds.push_back(shapeWorldBounds(e));
      if (isStillSphere(e)) {
        inst.transform = static_cast<uint32_t>(sphereBounds_.size());
        sphereBounds_.emplace_back(e.worldFromObject);
      }
    }
    instances_.push_back(inst);
  }
  // Many small meshes build side by side; a big one parallelises inside.
  tbb::parallel_for(size_t{0}, meshTrees_.size(), [this](size_t i) {
    MeshTree &mt = meshTrees_[i];
    if (mt.motion) {
      mt.tree = buildMovingMeshTree(*mt.motion);
      return;
    }
    mt.tree = buildMeshTree(*mt.mesh);
    std::span<const uint32_t> refs = mt.tree.primIndices();
    mt.packets.resize(refs.size() / kPacketLanes);
    tbb::parallel_for(size_t{0}, refs.size(), [&](size_t r) {
      const uint32_t *idx = mt.mesh->triangleIndices.data() + 3 * size_t{refs[r]};
      const std::vector<Vec3f> &pos = mt.mesh->positions;
      mt.packets[r / kPacketLanes].set(r % kPacketLanes, pos[idx[0]], pos[idx[1]], pos[idx[2]]);
    });
  });
  for (const MeshTree &mt : meshTrees_) {
    stats_.primitives += mt.mesh->triangleIndices.size() / 3;
    usePackets_ = usePackets_ || mt.tree.nodes().size() >= kPacketMinNodes;
  }
  top_ = KdTree::build(topBounds, [&topBounds](uint32_t i, const Bounds3 &box) {
    Bounds3 b = topBounds[i];
    b.lo = max(b.lo, box.lo);
    b.hi = min(b.hi, box.hi);
    return b;
  });
  usePackets_ = usePackets_ || top_.nodes().size() >= kPacketMinNodes;
  if (instances_.size() > 1) flat_ = FlatInstances(topBounds);
  if (flat_.empty() && instances_.size() > 1 && instances_.size() <= kFanInstances)
    fanBoxes_ = topBounds;

  stats_.buildSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats_.memoryBytes = top_.memoryBytes() + instances_.capacity() * sizeof(Instance) +
                       transforms_.capacity() * sizeof(Transform) +
                       meshTrees_.capacity() * sizeof(MeshTree);
  for (const MeshTree &mt : meshTrees_)
    stats_.memoryBytes +=
        mt.tree.memoryBytes() + mt.packets.capacity() * sizeof(TrianglePacket);
}

// Inlined, with the ray-axis lambda, into both levels' callers: as calls of
// their own they cost gallery scenes (rays into small meshes, a floor in
// every scene) more instructions than the code before the prefilter
// (bench/HISTORY.md). The leaf test is a call of its own (see below).
template <bool AnyHit, KdRays Rays>
[[gnu::always_inline]] inline bool KdTreeAccelerator::intersectMesh(const Instance &inst,
                                                                    const Ray &ray, double &tBest,
                                                                    MeshHit &hit) const {
  // An identity-placed mesh (most are) reads the world ray where it lies: a
  // copy's 16-byte stores read back as 32-byte loads stall store forwarding.
  Ray placed;
  if (inst.transform != kIdentity) placed = objectRayOf(inst, ray);
  const Ray &objectRay = inst.transform == kIdentity ? ray : placed;
  const MeshTree &mt = meshTrees_[inst.meshTree];
  // A tree of one leaf (a floor's two triangles) has no walk to clip the
  // ray to its box. A shadow ray that starts outside the box on an axis
  // and does not move towards it along that axis cannot meet it (the
  // walk's clip drops it too): a floor's own shadow rays, and those above
  // it that pass through a cell it shares. (Not for the nearest hit: the
  // camera rays that come down to a floor pay the check for nothing.)
  if (AnyHit && !mt.motion && mt.tree.nodes().size() == 1 &&
      movesAwayFrom(objectRay, mt.tree.bounds()))
    return false;
  const WatertightRay wray(objectRay);
  if (mt.motion)
    return mt.tree.traverseLeaves<AnyHit, Rays>(
        objectRay, tBest, [&](uint32_t offset, uint32_t count, double &tTri) {
          return testMovingLeaf<AnyHit>(mt, wray, ray.time, offset, count, tTri, hit);
        });
  // Meshes of one or two triangles (a floor) only take the exact test.
  const PrefilterRay fray = mt.mesh->triangleIndices.size() > 3 * kDirectTestLimit
                                ? PrefilterRay(wray, mt.tree.bounds())
                                : PrefilterRay();
  return withRayAxis(wray.kz, [&](auto axis) __attribute__((always_inline)) {
    constexpr int kz = decltype(axis)::value;
    // A tree of one leaf (a floor's two triangles): the walk would only
    // clip the ray to its box (the ray set-up's three divisions) before the
    // leaf's test, and a ray the test hits crosses the box.
    if (mt.tree.nodes().size() == 1) {
      const KdNode &leaf = mt.tree.nodes()[0];
      return leaf.primCount() > 0 && testMeshLeaf<AnyHit, kz>(mt, wray, fray, leaf.primOffset(),
                                                              leaf.primCount(), tBest, hit);
    }
    return mt.tree.traverseLeaves<AnyHit, Rays>(
        objectRay, tBest, [&](uint32_t offset, uint32_t count, double &tTri) {
          return testMeshLeaf<AnyHit, kz>(mt, wray, fray, offset, count, tTri, hit);
        });
  });
}

template <bool AnyHit>
bool KdTreeAccelerator::testMovingLeaf(const MeshTree &mt, const WatertightRay &wray, double time,
                                       uint32_t offset, uint32_t count, double &tTri,
                                       MeshHit &hit) const {
  const uint32_t *refs = mt.tree.primIndices().data() + offset;
  const std::vector<uint32_t> &corners = mt.mesh->triangleIndices;
  bool hitHere = false;
  for (uint32_t j = 0; j < count; ++j) {
    const uint32_t *v = corners.data() + 3 * size_t{refs[j]};
    TriangleHitParams params;
    if (!intersectTriangle(wray, mt.motion->position(v[0], time), mt.motion->position(v[1], time),
                           mt.motion->position(v[2], time), tTri, params))
      continue;
    tTri = params.t;
    hit = {offset + j, params.b1, params.b2};
    if (AnyHit) return true;
    hitHere = true;
  }
  return hitHere;
}

template <bool AnyHit, int Kz>
[[gnu::always_inline]] inline bool
KdTreeAccelerator::testMeshLeaf(const MeshTree &mt, const WatertightRay &wray,
                                const PrefilterRay &fray, uint32_t offset, uint32_t count,
                                double &tTri, MeshHit &hit) const {
  // Packets of four leaf references, eight at a time in one call where the
  // CPU has AVX2: the float prefilter keeps the triangles that may be hit,
  // the exact test decides them in order.
  bool hitHere = false;
  const TrianglePacket *group = mt.packets.data() + offset / kPacketLanes;
  const bool direct = count <= kDirectTestLimit;
  // Up to 64 references per prefilter call (one call for the whole leaf
  // with AVX2; packet by packet otherwise).
  for (uint32_t first = 0; first < count; first += 64, group += 64 / kPacketLanes) {
    const uint32_t n = std::min(count - first, 64u);
    uint64_t lanes = direct     ? leafLanes(n)
                     : useAvx2_ ? prefilterLeafAvx2<Kz>(fray, group, n)
                                : prefilterLeaf<Kz>(fray, group, n);
    for (; lanes != 0; lanes &= lanes - 1) {
      const uint32_t lane = static_cast<uint32_t>(std::countr_zero(lanes));
      const TrianglePacket &packet = group[lane / kPacketLanes];
      const int k = lane % kPacketLanes;
      TriangleHitParams params;
      if (!intersectFloatTriangle<Kz>(wray, packet.corner(k, 0), packet.corner(k, 1),
                                      packet.corner(k, 2), tTri, params))
        continue;
      tTri = params.t;
      hit = {offset + first + lane, params.b1, params.b2};
      if (AnyHit) return true;
      hitHere = true;
    }
  }
  return hitHere;
}

template <bool AnyHit>
uint32_t KdTreeAccelerator::intersectMeshPacket(const Instance &inst, const Ray *rays,
                                                uint32_t lanes, double *tBest,
                                                MeshHit *hits) const {
  const MeshTree &mt = meshTrees_[inst.meshTree];
  const bool prefilter = mt.mesh->triangleIndices.size() > 3 * kDirectTestLimit;
  Ray objectRays[kRays];
  std::optional<WatertightRay> wrays[kRays];
  PrefilterRay frays[kRays];
  for (int i = 0; i < kRays; ++i) {
    if (!(lanes >> i & 1u)) continue;
    objectRays[i] = objectRayOf(inst, rays[i]);
    wrays[i].emplace(objectRays[i]);
    if (prefilter) frays[i] = PrefilterRay(*wrays[i], mt.tree.bounds());
  }
  return mt.tree.traversePacket<AnyHit>(
      objectRays, lanes, tBest,
      [&](uint32_t offset, uint32_t count, uint32_t in, double *tTri) {
        uint32_t found = 0;
        for (; in != 0; in &= in - 1) {
          const int i = std::countr_zero(in);
          const bool hit = withRayAxis(wrays[i]->kz, [&](auto axis) {
            constexpr int kz = decltype(axis)::value;
            return testMeshLeaf<AnyHit, kz>(mt, *wrays[i], frays[i], offset, count, tTri[i],
                                            hits[i]);
          });
          found |= static_cast<uint32_t>(hit) << i;
        }
        return found;
      });
}

template <KdRays Rays>
[[gnu::always_inline]] inline bool
KdTreeAccelerator::nearestInstance(uint32_t prim, const Ray &ray, double &tBest, Hit &hit,
                                   TriangleCandidate &best, bool &bestIsTriangle) const {
  const Instance &inst = instances_[prim];
  const Entity &entity = scene_.entities[inst.entity];
  if (moving_.misses(inst.entity, ray, tBest)) return false;
  if (inst.meshTree == kAnalytic) {
    if (passesStillSphere(inst, ray)) return false;
    Hit candidate;
    if (!intersectShape(entity, inst.entity, ray, tBest, candidate) || !(candidate.t < tBest))
      return false;
    hit = candidate;
    tBest = candidate.t;
    bestIsTriangle = false;
    return true;
  }
  MeshHit meshHit;
  if (!intersectMesh<false, Rays>(inst, ray, tBest, meshHit)) return false;
  best = {inst.entity, inst.meshTree, meshHit};
  bestIsTriangle = true;
  return true;
}

template <KdRays Rays>
[[gnu::always_inline]] inline bool
KdTreeAccelerator::nearestBounded(const Ray &ray, Hit &hit, TriangleCandidate &best,
                                  bool &bestIsTriangle, double &tMax,
                                  const FlatInstances *list) const {
  // The nearest triangle is only recorded during traversal (as its leaf
  // reference); its Hit is filled once at the end. Analytic shapes write
  // theirs into `hit` as they are found (a nearer find overwrites it).
  bestIsTriangle = false;
  auto testInstance = [&](uint32_t prim, double &tBest) {
    return nearestInstance<Rays>(prim, ray, tBest, hit, best, bestIsTriangle);
  };
  // A few entities: their boxes in a list (flat_instances.h). One: the
  // top-level tree would only clip the ray to its bounds. More: an entity
  // met again in a later top-level leaf is skipped.
  if (list) return !list->empty() && list->forEachCrossed<false>(ray, tMax, testInstance);
  if (!flat_.empty()) return flat_.forEachCrossed<false>(ray, tMax, testInstance);
  Mailbox mailbox;
  return instances_.size() == 1
             ? testInstance(0, tMax)
             : top_.traverse<false, Rays>(ray, tMax, [&](uint32_t prim, double &tBest) {
                 return mailbox.firstVisit(prim) && testInstance(prim, tBest);
               });
}

uint32_t KdTreeAccelerator::nearestInStillSphere(const Instance &inst, const Ray *rays,
                                                uint32_t in, double *tBest, Hit *hits) const {
  // Its bound first (passesStillSphere lane by lane), then the four rays'
  // test (intersectStillSphereLanes). Lanes outside `in` read its first
  // ray.
  const Ray *laneRays[kRays];
  double bound[kRays];
  const int first = std::countr_zero(in);
  for (int i = 0; i < kRays; ++i) {
    const int r = (in >> i & 1u) ? i : first;
    laneRays[i] = &rays[r];
    bound[i] = tBest[r];
  }
  in &= ~sphereBounds_[inst.transform].missesLines(laneRays);
  if (in == 0) return 0;
  Hit got[kRays];
  Hit *const out[kRays] = {&got[0], &got[1], &got[2], &got[3]};
  uint32_t found = 0;
  for (uint32_t hit = intersectStillSphereLanes(scene_.entities[inst.entity], inst.entity,
                                                laneRays, bound, in, out);
       hit != 0; hit &= hit - 1) {
    const int i = std::countr_zero(hit);
    if (!(got[i].t < tBest[i])) continue;
    hits[i] = got[i];
    tBest[i] = got[i].t;
    found |= 1u << i;
  }
  return found;
}

void KdTreeAccelerator::nearestInList(const FlatInstances &list, const Ray *rays, int n,
                                      Hit *hits, TriangleCandidate *best, bool *bestIsTriangle,
                                      double *tMax, uint8_t *found) const {
  FlatInstances::Walk walks[kRays];
  int next[kRays];
  uint32_t walking = 0;
  FlatInstances::Start how[kRays];
  const Ray *starts[kRays];
  for (int k = 0; k < kRays; ++k) starts[k] = &rays[k < n ? k : 0];
  if (!list.empty()) list.start(starts, (1u << n) - 1, walks, how);
  for (int i = 0; i < n; ++i) {
    bestIsTriangle[i] = false;
    tMax[i] = rays[i].tMax;
    found[i] = 0;
    if (list.empty()) continue;
    switch (how[i]) {
    case FlatInstances::Start::None: break;
    case FlatInstances::Start::Parallel: // box by box, alone
      found[i] = nearestBounded<KdRays::Coherent>(rays[i], hits[i], best[i], bestIsTriangle[i],
                                                  tMax[i], &list);
      break;
    case FlatInstances::Start::Boxes: walking |= 1u << i; break;
    }
  }
  // Round by round, each ray's next box; the rays whose next box is the
  // same are tested together.
  while (walking != 0) {
    for (uint32_t w = walking; w != 0; w &= w - 1) {
      const int i = std::countr_zero(w);
      next[i] = list.next(walks[i], tMax[i]);
      if (next[i] < 0) walking &= ~(1u << i);
    }
    for (uint32_t left = walking; left != 0;) {
      const int box = next[std::countr_zero(left)];
      uint32_t same = 0;
      for (uint32_t w = left; w != 0; w &= w - 1)
        if (next[std::countr_zero(w)] == box) same |= 1u << std::countr_zero(w);
      left &= ~same;
      const uint32_t prim = list.id(box);
      const Instance &inst = instances_[prim];
      if (inst.meshTree == kAnalytic && inst.transform != kIdentity &&
          !moving_.moves(inst.entity) && (same & (same - 1)) != 0) {
        // A still sphere met by several rays: four at once.
        for (uint32_t hit = nearestInStillSphere(inst, rays, same, tMax, hits); hit != 0;
             hit &= hit - 1) {
          const int i = std::countr_zero(hit);
          bestIsTriangle[i] = false;
          found[i] = 1;
        }
        continue;
      }
      for (; same != 0; same &= same - 1) {
        const int i = std::countr_zero(same);
        if (nearestInstance<KdRays::Coherent>(prim, rays[i], tMax[i], hits[i], best[i],
                                              bestIsTriangle[i]))
          found[i] = 1;
      }
    }
  }
}

template <KdRays Rays> bool KdTreeAccelerator::intersectRay(const Ray &ray, Hit &hit) const {
  TriangleCandidate best;
  bool bestIsTriangle = false;
  double tMax = ray.tMax;
  const bool found = nearestBounded<Rays>(ray, hit, best, bestIsTriangle, tMax);
  if (found && bestIsTriangle) {
    uint32_t triangle = meshTrees_[best.meshTree].tree.primIndices()[best.mesh.ref];
    fillTriangleHit(scene_.entities[best.entity], best.entity, triangle, tMax, best.mesh.b1,
                    best.mesh.b2, ray, frameOrigin_, hit);
  }
  return unbounded_.empty() ? found : unbounded_.intersect(ray, hit, found);
}

template <KdRays Rays>
[[gnu::always_inline]] inline bool KdTreeAccelerator::occludedBounded(const Ray &ray,
                                                                  uint32_t *blocker) const {
  auto testInstance = [&](uint32_t prim, double &) {
    const Instance &inst = instances_[prim];
    if (moving_.misses(inst.entity, ray, ray.tMax)) return false;
    if (inst.meshTree == kAnalytic) {
      const Entity &entity = scene_.entities[inst.entity];
      const bool blocks =
          inst.transform == kIdentity
              ? occludedShape(entity, ray)
              : !passesStillSphere(inst, ray) && occludedStillSphere(entity, ray, ray.tMax);
      if (blocks && blocker) *blocker = inst.entity;
      return blocks;
    }
    double tObject = ray.tMax;
    MeshHit unused;
    return intersectMesh<true, Rays>(inst, ray, tObject, unused);
  };
  double tMax = ray.tMax;
  if (!flat_.empty()) return flat_.forEachCrossed<true>(ray, tMax, testInstance);
  Mailbox mailbox;
  return instances_.size() == 1
             ? testInstance(0, tMax)
             : top_.traverse<true, Rays>(ray, tMax, [&](uint32_t prim, double &tBest) {
                 return mailbox.firstVisit(prim) && testInstance(prim, tBest);
               });
}

template <KdRays Rays>
bool KdTreeAccelerator::occludedRay(const Ray &ray, uint32_t *blocker) const {
  if (!unbounded_.empty() && unbounded_.occluded(ray)) return true;
  return occludedBounded<Rays>(ray, blocker);
}

bool KdTreeAccelerator::intersect(const Ray &ray, Hit &hit) const {
  return intersectRay<KdRays::Incoherent>(ray, hit);
}

bool KdTreeAccelerator::occluded(const Ray &ray) const {
  return occludedRay<KdRays::Incoherent>(ray);
}

template <bool AnyHit>
uint32_t KdTreeAccelerator::packetQuery(const Ray *rays, uint32_t lanes, double *tMax,
                                        PacketFinds *finds, uint32_t *blockers) const {
  // Each lane meets the entities in the order its own walk does and keeps
  // its nearest find as intersectRay does. The lanes share one mailbox: it
  // skips fewer or other repeats than a lane's own would, and a repeat
  // finds nothing nearer (Mailbox), so the finds are the same.
  PacketMailbox mailbox;
  // Shadow rays: the packet's rays in lanes once, for the still spheres'
  // bounds (SphereBound::missesLines), which settle most of the lanes a
  // leaf's sphere meets four at a time. (Lanes outside `lanes` read the
  // first lane's ray.)
  lanes::RayLanes rayLanes;
  if (AnyHit) {
    const int firstLane = std::countr_zero(lanes);
    const Ray *laneRays[kRays];
    for (int i = 0; i < kRays; ++i) laneRays[i] = &rays[(lanes >> i & 1u) ? i : firstLane];
    lanes::loadRays(laneRays, rayLanes);
  }
  auto testInstance = [&](uint32_t prim, uint32_t in, double *tBest) {
    const Instance &inst = instances_[prim];
    uint32_t found = 0;
    if (moving_.moves(inst.entity))
      for (uint32_t m = in; m != 0; m &= m - 1) {
        const int i = std::countr_zero(m);
        if (moving_.misses(inst.entity, rays[i], tBest[i])) in &= ~(1u << i);
      }
    if (inst.meshTree == kAnalytic) {
      const Entity &entity = scene_.entities[inst.entity];
      const bool stillSphere = inst.transform != kIdentity;
      if (AnyHit && stillSphere) in &= ~sphereBounds_[inst.transform].missesLines(rayLanes);
      if (!AnyHit && stillSphere && in != 0) {
        found = nearestInStillSphere(inst, rays, in, tBest, finds->shapeHits);
        finds->triangleLanes &= ~found;
        return found;
      }
      for (; in != 0; in &= in - 1) {
        const int i = std::countr_zero(in);
        if (!AnyHit && passesStillSphere(inst, rays[i])) continue;
        if (AnyHit) {
          if (!(stillSphere ? occludedStillSphere(entity, rays[i], tBest[i])
                            : occludedShape(entity, rays[i], tBest[i])))
            continue;
          if (blockers) blockers[i] = inst.entity;
        } else {
          Hit candidate;
          if (!intersectShape(entity, inst.entity, rays[i], tBest[i], candidate) ||
              !(candidate.t < tBest[i]))
            continue;
          finds->shapeHits[i] = candidate;
          tBest[i] = candidate.t;
          finds->triangleLanes &= ~(1u << i);
        }
        found |= 1u << i;
      }
      return found;
    }
    MeshHit meshHits[kRays];
    const MeshTree &mt = meshTrees_[inst.meshTree];
    if (mt.tree.nodes().size() >= kPacketMinNodes && !mt.motion) {
      found = intersectMeshPacket<AnyHit>(inst, rays, in, tBest, meshHits);
    } else {
      for (uint32_t m = in; m != 0; m &= m - 1) {
        const int i = std::countr_zero(m);
        if (intersectMesh<AnyHit, KdRays::Coherent>(inst, rays[i], tBest[i], meshHits[i]))
          found |= 1u << i;
      }
    }
    if (!AnyHit)
      for (uint32_t f = found; f != 0; f &= f - 1) {
        const int i = std::countr_zero(f);
        finds->triangles[i] = {inst.entity, inst.meshTree, meshHits[i]};
        finds->triangleLanes |= 1u << i;
      }
    return found;
  };
  if (instances_.size() == 1) return testInstance(0, lanes, tMax);
  const uint32_t *topPrims = top_.primIndices().data();
  return top_.traversePacket<AnyHit>(
      rays, lanes, tMax, [&](uint32_t offset, uint32_t count, uint32_t in, double *tBest) {
        uint32_t found = 0;
        for (uint32_t k = 0; k < count && in != 0; ++k) {
          const uint32_t prim = topPrims[offset + k];
          const uint32_t first = mailbox.firstVisits(prim, in);
          if (first == 0) continue;
          const uint32_t hit = testInstance(prim, first, tBest);
          found |= hit;
          if (AnyHit) in &= ~hit;
        }
        return found;
      });
}

bool KdTreeAccelerator::fanList(const Ray *rays, size_t n, FlatInstances &list) const {
  RayFan fan;
  if (fanBoxes_.empty() || !fan.gather(rays, n)) return false;
  list = FlatInstances();
  for (uint32_t i = 0; i < fanBoxes_.size(); ++i) {
    if (!fan.mayCross(fanBoxes_[i])) continue;
    if (list.full()) return false;
    list.add(fanBoxes_[i], i);
  }
  return true;
}

void KdTreeAccelerator::intersectCoherent(const Ray *rays, size_t count, Hit *hits,
                                          uint8_t *found) const {
  // The mesh hits of a run of rays are filled together once their walks are
  // done: fillTriangleHits fills identity-placed ones several at a time in
  // SIMD lanes (the same Hits, bit for bit, as one at a time), as Embree's
  // coherent query does.
  constexpr size_t kChunk = 8 * kRays;
  TriangleHitQuery queries[kChunk];
  // Runs of 128 rays (8 rows of a tile's 16 pixels) for fanList: fewer cull
  // fewer boxes for more set-up, more cull fewer.
  constexpr size_t kFanRun = 4 * kChunk;
  FlatInstances fan;
  const FlatInstances *list = nullptr;
  for (size_t chunk = 0; chunk < count; chunk += kChunk) {
    if (!usePackets_ && chunk % kFanRun == 0)
      list = fanList(rays + chunk, std::min(kFanRun, count - chunk), fan) ? &fan : nullptr;
    const size_t chunkEnd = std::min(count, chunk + kChunk);
    size_t nq = 0;
    auto addQuery = [&](const TriangleCandidate &best, double t, size_t r) {
      const uint32_t triangle = meshTrees_[best.meshTree].tree.primIndices()[best.mesh.ref];
      queries[nq++] = {&scene_.entities[best.entity], best.entity, triangle, t, best.mesh.b1,
                       best.mesh.b2, &rays[r], &hits[r]};
    };
    const FlatInstances *flat = list ? list : flat_.empty() ? nullptr : &flat_;
    if (!usePackets_ && flat) {
      // A few entities: the rays four at a time (nearestInList).
      for (size_t first = chunk; first < chunkEnd; first += kRays) {
        const int n = static_cast<int>(std::min<size_t>(kRays, chunkEnd - first));
        TriangleCandidate best[kRays];
        bool bestIsTriangle[kRays];
        double tMax[kRays];
        nearestInList(*flat, rays + first, n, hits + first, best, bestIsTriangle, tMax,
                      found + first);
        for (int i = 0; i < n; ++i)
          if (found[first + i] && bestIsTriangle[i]) addQuery(best[i], tMax[i], first + i);
      }
    } else if (!usePackets_) {
      for (size_t r = chunk; r < chunkEnd; ++r) {
        TriangleCandidate best;
        bool bestIsTriangle = false;
        double tMax = rays[r].tMax;
        found[r] = nearestBounded<KdRays::Coherent>(rays[r], hits[r], best, bestIsTriangle,
                                                    tMax, list)
                       ? 1
                       : 0;
        if (found[r] && bestIsTriangle) addQuery(best, tMax, r);
      }
    } else {
      for (size_t first = chunk; first < chunkEnd; first += kRays) {
        const int n = static_cast<int>(std::min<size_t>(kRays, chunkEnd - first));
        const Ray *packet = rays + first;
        double tMax[kRays] = {};
        PacketFinds finds;
        finds.shapeHits = hits + first;
        for (int i = 0; i < n; ++i) tMax[i] = packet[i].tMax;
        const uint32_t hitLanes = packetQuery<false>(packet, (1u << n) - 1, tMax, &finds);
        for (int i = 0; i < n; ++i) {
          found[first + i] = static_cast<uint8_t>(hitLanes >> i & 1u);
          if (hitLanes >> i & finds.triangleLanes >> i & 1u)
            addQuery(finds.triangles[i], tMax[i], first + i);
        }
      }
    }
    fillTriangleHits(queries, nq, frameOrigin_);
  }
  if (!unbounded_.empty())
    for (size_t i = 0; i < count; ++i) found[i] = unbounded_.intersect(rays[i], hits[i], found[i]);
}

void KdTreeAccelerator::occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                                         uint32_t *blockers) const {
  if (blockers) std::fill_n(blockers, count, kNoEntity);
  if (!usePackets_) {
    for (size_t i = 0; i < count; ++i)
      occluded[i] =
          occludedRay<KdRays::Incoherent>(rays[i], blockers ? blockers + i : nullptr) ? 1 : 0;
    return;
  }
  for (size_t first = 0; first < count; first += kRays) {
    const int n = static_cast<int>(std::min<size_t>(kRays, count - first));
    double tMax[kRays] = {};
    for (int i = 0; i < n; ++i) tMax[i] = rays[first + i].tMax;
    const uint32_t blocked = packetQuery<true>(rays + first, (1u << n) - 1, tMax, nullptr,
                                               blockers ? blockers + first : nullptr);
    for (int i = 0; i < n; ++i) occluded[first + i] = static_cast<uint8_t>(blocked >> i & 1u);
  }
  if (!unbounded_.empty())
    for (size_t i = 0; i < count; ++i)
      if (!occluded[i]) occluded[i] = unbounded_.occluded(rays[i]);
}

double KdTreeAccelerator::rawSeconds(const Ray *rays, size_t count, RawQuery query) const {
  const bool packets = usePackets_ && (query == RawQuery::ClosestPackets ||
                                       query == RawQuery::OcclusionPackets);
  const bool closest = query == RawQuery::Closest || query == RawQuery::ClosestPackets;
  std::vector<Hit> scratch(kRays);
  size_t found = 0;
  const auto start = std::chrono::steady_clock::now();
  for (size_t first = 0; first < count; first += packets ? kRays : 1) {
    if (!packets) {
      if (closest) {
        TriangleCandidate best;
        bool bestIsTriangle = false;
        double tMax = rays[first].tMax;
        found += query == RawQuery::Closest
                     ? nearestBounded<KdRays::Incoherent>(rays[first], scratch[0], best,
                                                          bestIsTriangle, tMax)
                     : nearestBounded<KdRays::Coherent>(rays[first], scratch[0], best,
                                                        bestIsTriangle, tMax);
      } else {
        found += occludedBounded<KdRays::Incoherent>(rays[first]);
      }
      continue;
    }
    const int n = static_cast<int>(std::min<size_t>(kRays, count - first));
    double tMax[kRays] = {};
    for (int i = 0; i < n; ++i) tMax[i] = rays[first + i].tMax;
    PacketFinds finds;
    finds.shapeHits = scratch.data();
    found += std::popcount(closest ? packetQuery<false>(rays + first, (1u << n) - 1, tMax, &finds)
                                   : packetQuery<true>(rays + first, (1u << n) - 1, tMax, nullptr));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // What the walks found, stored where the compiler must store it, so that
  // walks whose results are otherwise unused are not optimised away.
  [[maybe_unused]] volatile size_t foundSink = found;
  return seconds;
}

} // namespace lray
