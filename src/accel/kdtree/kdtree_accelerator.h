// Pipeline: acceleration (kd-tree backend). The project's own backend behind
// Accelerator: two levels, like Embree's instancing. Each distinct MeshData
// gets one bottom-level SAH kd-tree over its triangles in mesh object space
// (copies of a mesh share it); a top-level kd-tree holds the entities
// (analytic shapes by their world bounds, mesh instances by the world bounds
// of their transformed object bounds). Shapes and triangle hit records come
// from the shared code in geometry/shape.h, as with Embree.
#pragma once

#include "accel/accelerator.h"
#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/triangle_prefilter.h"
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
  /// Loops over single rays (the kd-tree has no packet traversal): camera
  /// rays by the tree walk whose branches predict well on neighbouring rays
  /// (KdRays::Coherent; single rays take the Incoherent one), shadow rays
  /// as single rays do (see occludedCoherent).
  void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const override;
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded) const override;
  /// primitives: analytic shapes + triangles of the distinct meshes;
  /// instances: mesh entities (each an instance of a bottom-level tree).
  AcceleratorStats stats() const override { return stats_; }

  /// The top-level tree over entities (for tests and benchmarks).
  const KdTree &topLevelTree() const { return top_; }
  /// Number of bottom-level trees (distinct meshes).
  size_t meshTreeCount() const { return meshTrees_.size(); }
  /// Bottom-level tree i, over one distinct mesh's triangles in object space.
  const KdTree &meshTree(size_t i) const { return meshTrees_[i].tree; }

private:
  static constexpr uint32_t kAnalytic = ~0u;

  struct MeshTree {
    const MeshData *mesh = nullptr;
    KdTree tree;
    /// The triangles' corners copied out of the mesh in the tree's leaf
    /// order, four leaf references per packet (leaves are padded to
    /// multiples of four): a leaf's triangles are read from one contiguous
    /// run, in SIMD lanes, instead of through the index and position arrays.
    std::vector<TrianglePacket> packets;
  };
  static constexpr uint32_t kIdentity = ~0u;
  /// One top-level primitive: an entity and, for meshes, how to reach its
  /// tree. 12 bytes: a scene of a million analytic shapes keeps a million.
  struct Instance {
    uint32_t entity = 0;
    uint32_t meshTree = kAnalytic;
    /// Meshes: the index of objectFromWorld in transforms_, or kIdentity
    /// (object space == world space: the ray is not transformed).
    uint32_t transform = kIdentity;
  };
  static_assert(sizeof(Instance) == 12);

  /// A mesh hit as found during traversal: the leaf reference and barycentrics.
  struct MeshHit {
    uint32_t ref = 0;
    double b1 = 0, b2 = 0;
  };
  /// The nearest (AnyHit: any) triangle of a mesh instance with t in
  /// (ray.tMin, tBest), `ray` in world space; lowers tBest to a hit's t.
  template <bool AnyHit, KdRays Rays>
  bool intersectMesh(const Instance &inst, const Ray &ray, double &tBest, MeshHit &hit) const;
  /// intersect() and occluded() by either walk of the trees.
  template <KdRays Rays> bool intersectRay(const Ray &ray, Hit &hit) const;
  template <KdRays Rays> bool occludedRay(const Ray &ray) const;

  const Scene &scene_;
  /// The float frame of fillTriangleHit's error bound (same as Embree's, so
  /// both backends spawn secondary rays from the same points).
  Vec3 frameOrigin_;
  /// Leaf triangles go through the prefilter two packets at a time (AVX2).
  bool useAvx2_;
  std::vector<MeshTree> meshTrees_;
  std::vector<Instance> instances_;
  /// objectFromWorld of each transformed mesh instance.
  std::vector<Transform> transforms_;
  KdTree top_;
  AcceleratorStats stats_;
};

} // namespace lray
