// Pipeline: acceleration (kd-tree backend). The project's own backend behind
// Accelerator: two levels, like Embree's instancing. Each distinct MeshData
// gets one bottom-level SAH kd-tree over its triangles in mesh object space
// (copies of a mesh share it); a top-level kd-tree holds the entities
// (analytic shapes by their world bounds, mesh instances by the world bounds
// of their transformed object bounds). Shapes and triangle hit records come
// from the shared code in geometry/shape.h, as with Embree.
#pragma once

#include "accel/accelerator.h"
#include "accel/moving_boxes.h"
#include "accel/unbounded_shapes.h"
#include "accel/kdtree/flat_instances.h"
#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/ray_fan.h"
#include "accel/kdtree/triangle_prefilter.h"
#include "geometry/shape.h"
#include "geometry/shapes/sphere_bound.h"
#include "math/transform.h"

#include <cstdint>
#include <vector>

namespace lray {

/// SAH kd-tree backend (--backend kdtree).
class KdTreeAccelerator final : public Accelerator {
public:
  /// Builds both levels over `scene` (which must outlive this object).
  explicit KdTreeAccelerator(const Scene &scene);

  bool intersect(const Ray &ray, Hit &hit) const override;
  bool occluded(const Ray &ray) const override;
  /// Packets of KdTree::kPacketRays consecutive rays through both levels
  /// (KdTree::traversePacket) where usesPackets(): the same results as
  /// single rays by the general loop. Otherwise single rays: camera rays by
  /// the general loop, whose branches predict well on neighbouring rays
  /// (KdRays::Coherent), shadow rays as intersect() and occluded() take them.
  void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const override;
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                        uint32_t *blockers) const override;
  /// primitives: analytic shapes + triangles of the distinct meshes;
  /// instances: mesh entities (each an instance of a bottom-level tree).
  AcceleratorStats stats() const override { return stats_; }

  /// The top-level tree over entities (for tests and benchmarks).
  const KdTree &topLevelTree() const { return top_; }
  /// Number of bottom-level trees (distinct meshes).
  size_t meshTreeCount() const { return meshTrees_.size(); }
  /// Whether intersectCoherent and occludedCoherent trace packets (some
  /// tree has kPacketMinNodes nodes or more); otherwise single rays.
  bool usesPackets() const { return usePackets_; }
  /// Bottom-level tree i, over one distinct mesh's triangles in object space.
  const KdTree &meshTree(size_t i) const { return meshTrees_[i].tree; }

  /// For bench/throughput: how long the trees alone take for these queries
  /// (seconds, this thread), as EmbreeAccelerator::rawSeconds: the same
  /// walks as above (single rays, or packets where usesPackets()) with the
  /// analytic shapes' tests, but no mesh hit filled, no plane tested.
  double rawSeconds(const Ray *rays, size_t count, RawQuery query) const;

private:
  static constexpr uint32_t kAnalytic = ~0u;

  struct MeshTree {
    const MeshData *mesh = nullptr;
    /// Set for a mesh whose vertices move (Entity::vertexMotion): the tree
    /// holds each triangle's bounds over the shutter, and each ray meets
    /// the triangles where they are at its time (no packets).
    const MeshMotion *motion = nullptr;
    KdTree tree;
    /// The triangles' corners copied out of the mesh in the tree's leaf
    /// order, four leaf references per packet (leaves are padded to
    /// multiples of four): a leaf's triangles are read from one contiguous
    /// run, in SIMD lanes, instead of through the index and position arrays.
    std::vector<TrianglePacket> packets;
  };
  static constexpr uint32_t kIdentity = ~0u;
  /// A moving mesh (Entity::motion): its transform at each ray's time.
  static constexpr uint32_t kMoving = ~0u - 1;
  /// One top-level primitive: an entity and, for meshes, how to reach its
  /// tree. 12 bytes: a scene of a million analytic shapes keeps a million.
  struct Instance {
    uint32_t entity = 0;
    uint32_t meshTree = kAnalytic;
    /// Meshes: the index of objectFromWorld in transforms_, or kIdentity
    /// (object space == world space: the ray is not transformed), or kMoving.
    /// A still Sphere (isStillSphere): the index of its SphereBound in
    /// sphereBounds_; other analytic shapes: kIdentity.
    uint32_t transform = kIdentity;
  };
  static_assert(sizeof(Instance) == 12);

  /// A mesh hit as found during traversal: the leaf reference and barycentrics.
  struct MeshHit {
    uint32_t ref = 0;
    double b1 = 0, b2 = 0;
  };
  static constexpr int kRays = KdTree::kPacketRays;
  /// A mesh hit of a closest-hit query, before its Hit is filled.
  struct TriangleCandidate {
    uint32_t entity = 0, meshTree = 0;
    MeshHit mesh;
  };
  /// The nearest finds of a packet's closest-hit query: lane i's nearest
  /// is triangles[i] where bit i of triangleLanes is set, else the shape
  /// hit written to shapeHits[i].
  struct PacketFinds {
    Hit *shapeHits = nullptr;
    TriangleCandidate triangles[KdTree::kPacketRays];
    uint32_t triangleLanes = 0;
  };
  /// testMeshLeaf for a tree whose triangles move (MeshTree::motion): the
  /// exact test on the corners at the ray's time.
  template <bool AnyHit>
  bool testMovingLeaf(const MeshTree &mt, const WatertightRay &wray, double time, uint32_t offset,
                      uint32_t count, double &tTri, MeshHit &hit) const;
  /// An analytic instance: true only where it is a still sphere that the
  /// line of `ray` passes by a clear margin (SphereBound), so that its own
  /// test would find nothing.
  bool passesStillSphere(const Instance &inst, const Ray &ray) const {
    return inst.transform != kIdentity && sphereBounds_[inst.transform].missesLine(ray);
  }
  /// `ray` (world space) in the object space of mesh instance `inst`.
  Ray objectRayOf(const Instance &inst, const Ray &ray) const {
    if (inst.transform == kIdentity) return ray;
    if (inst.transform == kMoving) return objectSpaceRay(scene_.entities[inst.entity], ray);
    return transforms_[inst.transform].applyRay(ray);
  }
  /// The nearest (AnyHit: any) triangle of a mesh instance with t in
  /// (ray.tMin, tBest), `ray` in world space; lowers tBest to a hit's t.
  template <bool AnyHit, KdRays Rays>
  bool intersectMesh(const Instance &inst, const Ray &ray, double &tBest, MeshHit &hit) const;
  /// The leaf test of intersectMesh for one ray (Kz: its kz): references
  /// [offset, offset + count) of mt's tree, t in (tMin, tTri).
  template <bool AnyHit, int Kz>
  bool testMeshLeaf(const MeshTree &mt, const WatertightRay &wray, const PrefilterRay &fray,
                    uint32_t offset, uint32_t count, double &tTri, MeshHit &hit) const;
  /// intersectMesh for the lanes of a packet (bit i: rays[i]); returns the
  /// lanes that hit.
  template <bool AnyHit>
  uint32_t intersectMeshPacket(const Instance &inst, const Ray *rays, uint32_t lanes,
                               double *tBest, MeshHit *hits) const;
  /// A packet through both levels: the lanes that hit; for closest hits,
  /// each lane's nearest find in `finds`, with tMax lowered to its t; for
  /// any hit, where `blockers` is given, the analytic entity that blocked
  /// lane i in blockers[i] (left as it was where none did).
  template <bool AnyHit>
  uint32_t packetQuery(const Ray *rays, uint32_t lanes, double *tMax, PacketFinds *finds,
                       uint32_t *blockers = nullptr) const;
  /// intersect() and occluded() by either walk of the trees; occludedRay
  /// names the analytic entity it found blocking the ray in `blocker`
  /// where given (occludedBounded).
  template <KdRays Rays> bool intersectRay(const Ray &ray, Hit &hit) const;
  template <KdRays Rays> bool occludedRay(const Ray &ray, uint32_t *blocker = nullptr) const;
  /// Their walks over the bounded entities (the trees; no planes): the
  /// nearest find is an analytic shape's Hit in `hit`, or a triangle in
  /// `best` (then bestIsTriangle), its t in tMax; its Hit is not filled.
  /// `list`: the entities to test instead of the whole top level (fanList).
  template <KdRays Rays>
  bool nearestBounded(const Ray &ray, Hit &hit, TriangleCandidate &best, bool &bestIsTriangle,
                      double &tMax, const FlatInstances *list = nullptr) const;
  /// nearestBounded's test of instance `prim` for one ray: lowers tBest to
  /// the nearer hit it finds (an analytic shape's Hit in `hit`, a triangle
  /// in `best`).
  template <KdRays Rays>
  bool nearestInstance(uint32_t prim, const Ray &ray, double &tBest, Hit &hit,
                       TriangleCandidate &best, bool &bestIsTriangle) const;
  /// Still sphere `inst` (isStillSphere) against rays[i], i in `in`, four
  /// at once: where one finds a hit before tBest[i], hits[i] takes it and
  /// tBest[i] its t (the same as nearestInstance one ray at a time); the
  /// lanes that did.
  uint32_t nearestInStillSphere(const Instance &inst, const Ray *rays, uint32_t in,
                                double *tBest, Hit *hits) const;
  /// nearestBounded over `list` for rays[0, n) (n <= kRays), each ray's
  /// boxes in its own order, the rays that test the same entity next
  /// tested together (four at once on a still sphere): the same finds, per
  /// ray, as nearestBounded's. found[i]: whether ray i found anything.
  void nearestInList(const FlatInstances &list, const Ray *rays, int n, Hit *hits,
                     TriangleCandidate *best, bool *bestIsTriangle, double *tMax,
                     uint8_t *found) const;
  /// The entities whose boxes any of rays[0, n) may cross, as `list` (what
  /// it held is dropped): only where the rays form a RayFan and at most
  /// FlatInstances::kMaxInstances of the scene's boxes (fanBoxes_) pass it;
  /// false otherwise (the flat-list scenes at once: no fanBoxes_).
  bool fanList(const Ray *rays, size_t n, FlatInstances &list) const;
  /// occluded() without the unbounded entities; where `blocker` is given,
  /// the analytic entity found blocking the ray goes there.
  template <KdRays Rays> bool occludedBounded(const Ray &ray, uint32_t *blocker = nullptr) const;

  const Scene &scene_;
  /// The float frame of fillTriangleHit's error bound (same as Embree's, so
  /// both backends spawn secondary rays from the same points).
  Vec3 frameOrigin_;
  /// Leaf triangles go through the prefilter two packets at a time (AVX2).
  bool useAvx2_;
  /// Some tree is large enough for packets (kPacketMinNodes).
  bool usePackets_ = false;
  std::vector<MeshTree> meshTrees_;
  std::vector<Instance> instances_;
  /// The still spheres' bounds (Instance::transform), which settle most
  /// shadow rays that pass them before occludedStillSphere.
  std::vector<SphereBound> sphereBounds_;
  /// Planes: outside both levels, tested after them (closest) or before
  /// them (any hit).
  UnboundedShapes unbounded_;
  /// The top level as a list where the scene has few bounded entities
  /// (single rays; packets walk top_).
  FlatInstances flat_;
  /// The top level's boxes where the scene has at most kFanInstances
  /// bounded entities (more than one): fanList culls them for a run of
  /// camera rays.
  std::vector<Bounds3> fanBoxes_;
  static constexpr size_t kFanInstances = 32;
  /// Moving entities' bounds at each motion step: a ray's test at its time.
  MovingBoxes moving_;
  /// objectFromWorld of each transformed mesh instance.
  std::vector<Transform> transforms_;
  KdTree top_;
  AcceleratorStats stats_;
};

} // namespace lray
