// Pipeline: acceleration (Embree backend). Adapts Embree 3 to the
// Accelerator interface: analytic entities are user geometries whose
// callbacks forward to src/geometry/shape.h, meshes are triangle geometries
// built once per distinct MeshData and placed by one instance per entity.
// Embree types stay in embree_accelerator.cpp; this header only names the
// opaque handles.
#pragma once

#include "accel/accelerator.h"
#include "accel/moving_boxes.h"
#include "accel/unbounded_shapes.h"
#include "geometry/shapes/sphere_bound.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace lray {

/// The Embree backend (README.md, "Accuracy, and the two backends"). Rays are traced in single
/// precision by Embree; analytic shapes are still intersected in double precision from the caller's
/// own ray (the callbacks read it from the per-query context), and every Hit is filled by the
/// shared shape code.
class EmbreeAccelerator final : public Accelerator {
public:
  /// Builds the Embree scene over `scene`, which must outlive this object.
  /// Throws std::runtime_error if Embree reports an error while building.
  explicit EmbreeAccelerator(const Scene &scene);
  ~EmbreeAccelerator() override;
  EmbreeAccelerator(const EmbreeAccelerator &) = delete;
  EmbreeAccelerator &operator=(const EmbreeAccelerator &) = delete;

  /// Closest hit; single-ray Embree query (world space, t in units of |ray.d|).
  bool intersect(const Ray &ray, Hit &hit) const override;
  bool occluded(const Ray &ray) const override;
  /// 8-wide packets flagged coherent (camera rays of a tile).
  void intersectCoherent(const Ray *rays, size_t count, Hit *hits, uint8_t *found) const override;
  void occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                        uint32_t *blockers) const override;
  AcceleratorStats stats() const override { return stats_; }

  /// For bench/throughput: how long Embree alone takes for these queries
  /// (seconds, this thread): the same calls as above (single rays, or
  /// 8-wide coherent packets), with the context the analytic shapes'
  /// callbacks need, but no mesh hit filled, no plane tested, nothing kept.
  double rawSeconds(const Ray *rays, size_t count, RawQuery query) const;

  /// Per analytic entity: what its Embree callbacks need.
  struct ShapeRef {
    const Entity *entity = nullptr;
    uint32_t index = 0;
    RTCSceneTy *meshScene = nullptr; ///< a moving mesh: its triangle scene
    bool stillSphere = false; ///< occludedStillSphere tests it
    SphereBound sphereBound;  ///< a still sphere's: settles most shadow rays first
  };

private:
  void build();
  void release();

  const Scene &scene_;
  RTCDeviceTy *device_ = nullptr;
  RTCSceneTy *root_ = nullptr;
  std::vector<RTCSceneTy *> meshScenes_;
  /// All analytic entities form one user geometry; primID indexes this.
  std::vector<ShapeRef> shapeRefs_;
  /// The moving entities (analytic and mesh): one more user geometry with
  /// a time step per motion step; primID indexes this.
  std::vector<ShapeRef> movingRefs_;
  /// Planes: outside the Embree scene, tested after it (closest) or before
  /// it (any hit).
  UnboundedShapes unbounded_;
  /// The moving entities' bounds at each motion step: Embree's bounds for
  /// them, and each ray's test of its box before the entity's own.
  MovingBoxes moving_;
  /// Origin of the float frame Embree works in (geometry/float_frame.h).
  Vec3 frameOrigin_;
  /// Padded copies of vertex buffers whose capacity leaves no room for
  /// Embree's 16-byte read of the last vertex.
  std::vector<std::vector<Vec3f>> paddedPositions_;
  std::atomic<std::ptrdiff_t> embreeBytes_{0};
  AcceleratorStats stats_;
  std::atomic<int> errorCode_{0};
  char errorMessage_[256] = {}; ///< first error reported by Embree

  friend struct EmbreeCallbacks;
};

} // namespace lray
