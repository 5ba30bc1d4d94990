// Pipeline: acceleration (Embree backend). Every rtc* call of the program
// lives in this file. The scene is one top-level Embree scene holding
//  - one user geometry whose primitives are the analytic entities (its
//    callbacks only forward to geometry/shape.h), and
//  - one instance per mesh entity (geometry ID = entity index) of a
//    triangle scene built once per distinct MeshData over shared buffers;
//    a mesh whose only user has the identity transform is attached
//    directly instead (same ID), saving the instance level on every ray;
//  - when entities move while the shutter is open (Entity::motion), one
//    more user geometry holding them with a time step per motion step
//    (Embree's motion blur: its bounds at each step, the ray's time). A
//    moving mesh is traced there in its own triangle scene (one whose
//    vertices move has vertex buffers per step, blended by Embree), the ray
//    taken into object space by the mesh's transform at its time in double.
//    Embree's own instance motion is not used: its slerp approximates acos
//    and sin in single precision, and its instances would not be where the
//    kd-tree and the hit records put them.
// Queries carry the caller's double-precision rays in an extended
// RTCIntersectContext, so analytic shapes are intersected exactly as the
// kd-tree does and the callback's Hit is the one returned (no recomputation).
#include "accel/embree/embree_accelerator.h"
#include "accel/embree/embree_rays.h"

#include "geometry/float_frame.h"
#include "geometry/shape.h"
#include "geometry/triangle_prefetch.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace lray {

namespace {

constexpr float kInfinityF = std::numeric_limits<float>::infinity();

/// Embree's context followed by what the shape callbacks need. Rays are
/// found by RTCRay::id, which is their index in `rays` (Embree may split
/// packets, so the lane index is not reliable).
struct QueryContext {
  RTCIntersectContext base; // must stay first: Embree passes &base back
  const Ray *rays = nullptr;
  Hit *hits = nullptr;       ///< intersect only: where an accepted analytic hit goes
  double *bestT = nullptr;   ///< intersect only: t of the closest analytic hit so far
  uint32_t *blockers = nullptr; ///< occludedCoherent only: the analytic entity blocking a ray
};

/// Whether a triangle of `mesh` has no area (its corners' cross product,
/// in double from their floats, is zero).
bool hasZeroAreaTriangle(const MeshData &mesh) {
  const auto &index = mesh.triangleIndices;
  for (size_t t = 0; t + 2 < index.size(); t += 3) {
    const Vec3 a = toVec3(mesh.positions[index[t]]);
    if (cross(toVec3(mesh.positions[index[t + 1]]) - a, toVec3(mesh.positions[index[t + 2]]) - a) ==
        Vec3(0, 0, 0))
      return true;
  }
  return false;
}

/// Meshes placed as triangles in the world (`placeable`): at most this
/// many entities of one mesh, and this many triangles of shared meshes in all.
constexpr size_t kMaxPlacedCopies = 4;
constexpr size_t kMaxPlacedTriangles = size_t{1} << 20;

/// Whether an entity's transformed mesh (used by `uses` entities) goes into
/// the root scene as its own triangles placed in the world rather than as
/// an instance of one object-space BVH: Embree's packets of shadow rays pay
/// for crossing an instance's level (the 2011 examples' bunnies and teapot
/// render about a tenth faster placed, bench/HISTORY.md). A mesh that many
/// entities share stays instanced (one BVH for all its copies), and so does
/// one with a triangle of no area: placed in float, three collinear corners
/// would become a sliver that rays could hit. `placedTriangles` counts the
/// shared meshes' copies placed so far.
bool placeable(const MeshData &mesh, size_t uses, size_t &placedTriangles) {
  const size_t triangles = mesh.triangleIndices.size() / 3;
  if (uses > kMaxPlacedCopies) return false;
  if (uses > 1 && placedTriangles + triangles > kMaxPlacedTriangles) return false;
  if (hasZeroAreaTriangle(mesh)) return false;
  if (uses > 1) placedTriangles += triangles;
  return true;
}

} // namespace

/// Embree callbacks. None of them throws (the shape code does not) and none
/// allocates.
struct EmbreeCallbacks {
  static void error(void *user, RTCError code, const char *message) {
    auto *self = static_cast<EmbreeAccelerator *>(user);
    int expected = 0;
    // Keep the first error; copy without allocating (nothing may throw here).
    if (self->errorCode_.compare_exchange_strong(expected, static_cast<int>(code)))
      std::snprintf(self->errorMessage_, sizeof self->errorMessage_, "%s",
                    message ? message : "unknown error");
  }

  static bool memory(void *user, ssize_t bytes, bool /*post*/) {
    static_cast<EmbreeAccelerator *>(user)->embreeBytes_ += bytes;
    return true;
  }

  static void bounds(const RTCBoundsFunctionArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    setBounds(shapeWorldBounds(*self->shapeRefs_[args->primID].entity), self->frameOrigin_,
              *args->bounds_o);
  }

  /// `b` for Embree, in the float frame about `f`; the subtraction's
  /// rounding is covered by rounding outwards.
  static void setBounds(const Bounds3 &b, const Vec3 &f, RTCBounds &o) {
    o.lower_x = roundDown(b.lo.x - f.x);
    o.lower_y = roundDown(b.lo.y - f.y);
    o.lower_z = roundDown(b.lo.z - f.z);
    o.upper_x = roundUp(b.hi.x - f.x);
    o.upper_y = roundUp(b.hi.y - f.y);
    o.upper_z = roundUp(b.hi.z - f.z);
  }

  /// Writes a hit into lane i of Embree's hit records: its normal and
  /// barycentrics (float), and who was hit.
  static void setHit(RTCHitN *hits, unsigned n, unsigned i, float ngx, float ngy, float ngz,
                     float u, float v, unsigned primID, unsigned geomID, unsigned instID) {
    RTCHitN_Ng_x(hits, n, i) = ngx;
    RTCHitN_Ng_y(hits, n, i) = ngy;
    RTCHitN_Ng_z(hits, n, i) = ngz;
    RTCHitN_u(hits, n, i) = u;
    RTCHitN_v(hits, n, i) = v;
    RTCHitN_primID(hits, n, i) = primID;
    RTCHitN_geomID(hits, n, i) = geomID;
    RTCHitN_instID(hits, n, i, 0) = instID;
  }

  static void intersect(const RTCIntersectFunctionNArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    intersectShapeLanes(args, self->shapeRefs_[args->primID], nullptr);
  }

  /// The analytic entity `shape` for each valid lane (the shared shape
  /// code, with the caller's double ray). A moving entity (`moving`
  /// given): only the lanes whose ray meets its box at the ray's time.
  static void intersectShapeLanes(const RTCIntersectFunctionNArguments *args,
                                  const EmbreeAccelerator::ShapeRef &shape,
                                  const MovingBoxes *moving) {
    // Packets of four or eight rays (a single ray takes the scalar test).
    if (shape.stillSphere && !moving && args->N >= 4) return intersectSphereLanes(args, shape);
    auto *ctx = reinterpret_cast<QueryContext *>(args->context);
    const unsigned n = args->N;
    RTCRayN *rays = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN *hits = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned i = 0; i < n; ++i) {
      if (!args->valid[i]) continue;
      const unsigned id = RTCRayN_id(rays, n, i);
      const Ray &r = ctx->rays[id];
      // Closer than both the best analytic hit (double) and whatever
      // Embree has accepted since (a triangle's float t).
      const double tMax = std::min(std::min(r.tMax, ctx->bestT[id]),
                                   static_cast<double>(RTCRayN_tfar(rays, n, i)));
      if (moving && moving->misses(shape.index, r, tMax)) continue;
      if (shape.stillSphere && shape.sphereBound.missesLine(r)) continue;
      // Into the ray's hit directly (intersectShape writes it only on a
      // hit): a local copied there whole went through the stack.
      Hit &h = ctx->hits[id];
      if (!intersectShape(*shape.entity, shape.index, r, tMax, h)) continue;
      ctx->bestT[id] = h.t;
      RTCRayN_tfar(rays, n, i) = roundUp(h.t);
      setHit(hits, n, i, static_cast<float>(h.ng.x), static_cast<float>(h.ng.y),
             static_cast<float>(h.ng.z), static_cast<float>(h.u), static_cast<float>(h.v),
             args->primID, args->geomID, args->context->instID[0]);
    }
  }

  /// intersectShapeLanes for a still sphere: four lanes at a time, its
  /// bound (SphereBound) first, then one test of the four
  /// (intersectStillSphereLanes): the same hits as one lane at a time.
  static void intersectSphereLanes(const RTCIntersectFunctionNArguments *args,
                                   const EmbreeAccelerator::ShapeRef &shape) {
    auto *ctx = reinterpret_cast<QueryContext *>(args->context);
    const unsigned n = args->N;
    RTCRayN *rays = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN *hits = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned base = 0; base < n; base += 4) {
      // Lanes past N or invalid read the packet's first ray.
      const Ray *lane[4] = {ctx->rays, ctx->rays, ctx->rays, ctx->rays};
      double tMax[4] = {};
      unsigned id[4] = {};
      uint32_t open = 0;
      for (unsigned k = 0; k < 4 && base + k < n; ++k) {
        const unsigned i = base + k;
        if (!args->valid[i]) continue;
        id[k] = RTCRayN_id(rays, n, i);
        lane[k] = &ctx->rays[id[k]];
        // As intersectShapeLanes: below the best analytic hit and Embree's.
        tMax[k] = std::min(std::min(lane[k]->tMax, ctx->bestT[id[k]]),
                           static_cast<double>(RTCRayN_tfar(rays, n, i)));
        open |= 1u << k;
      }
      if (open == 0) continue;
      open &= ~shape.sphereBound.missesLines(lane);
      if (open == 0) continue;
      Hit *const out[4] = {&ctx->hits[id[0]], &ctx->hits[id[1]], &ctx->hits[id[2]],
                           &ctx->hits[id[3]]};
      for (uint32_t found = intersectStillSphereLanes(*shape.entity, shape.index, lane, tMax,
                                                      open, out);
           found != 0; found &= found - 1) {
        const unsigned k = static_cast<unsigned>(std::countr_zero(found)), i = base + k;
        const Hit &h = *out[k];
        ctx->bestT[id[k]] = h.t;
        RTCRayN_tfar(rays, n, i) = roundUp(h.t);
        setHit(hits, n, i, static_cast<float>(h.ng.x), static_cast<float>(h.ng.y),
               static_cast<float>(h.ng.z), static_cast<float>(h.u), static_cast<float>(h.v),
               args->primID, args->geomID, args->context->instID[0]);
      }
    }
  }

  /// Moving entities: bounds of time step `timeStep` such that Embree's
  /// linear blend of two neighbouring steps' bounds holds the entity over
  /// the segment between them (stepWorldBounds), widened by a few of
  /// float's ulps for the rounding of Embree's blend.
  static void movingBounds(const RTCBoundsFunctionArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    const EmbreeAccelerator::ShapeRef &ref = self->movingRefs_[args->primID];
    Bounds3 b = self->moving_.moves(ref.index) ? self->moving_.stepBox(ref.index, args->timeStep)
                                               : stepWorldBounds(*ref.entity, args->timeStep);
    if (!b.empty()) {
      const Vec3 &f = self->frameOrigin_;
      const double magnitude = std::max(maxAbsComponent(b.lo - f), maxAbsComponent(b.hi - f));
      const double pad = magnitude * 1e-6;
      b = {b.lo - Vec3(pad, pad, pad), b.hi + Vec3(pad, pad, pad)};
    }
    setBounds(b, self->frameOrigin_, *args->bounds_o);
  }

  /// A moving mesh's nearest triangle for ray `r` (world space, its time),
  /// nearer than `tfar`: traced in the mesh's own scene in object space.
  static bool movingMeshHit(const EmbreeAccelerator::ShapeRef &ref, const Ray &r, float tfar,
                            RTCRayHit &rh) {
    const Ray o = objectSpaceRay(*ref.entity, r);
    toRayHit1(o, Vec3(), rh);
    rh.ray.tfar = std::min(rh.ray.tfar, tfar);
    RTCIntersectContext inner;
    rtcInitIntersectContext(&inner);
    rtcIntersect1(ref.meshScene, &inner, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

  /// The box test at the ray's time (moving_boxes.h) before a moving
  /// entity's own: it pays for itself unless the entity only slides, when
  /// its inverse costs a few products (measured on bench/motion's crowd).
  static const MovingBoxes *boxTestFor(const EmbreeAccelerator &self,
                                       const EmbreeAccelerator::ShapeRef &ref) {
    const TransformMotion *motion = ref.entity->motion.get();
    return motion && motion->slides() ? nullptr : &self.moving_;
  }

  static void movingIntersect(const RTCIntersectFunctionNArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    const EmbreeAccelerator::ShapeRef &ref = self->movingRefs_[args->primID];
    const MovingBoxes *boxes = boxTestFor(*self, ref);
    if (!ref.entity->isMesh()) return intersectShapeLanes(args, ref, boxes);
    auto *ctx = reinterpret_cast<QueryContext *>(args->context);
    const unsigned n = args->N;
    RTCRayN *rays = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN *hits = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned i = 0; i < n; ++i) {
      if (!args->valid[i]) continue;
      const unsigned id = RTCRayN_id(rays, n, i);
      const float tfar = RTCRayN_tfar(rays, n, i);
      if (boxes && boxes->misses(ref.index, ctx->rays[id], tfar)) continue;
      RTCRayHit rh;
      if (!movingMeshHit(ref, ctx->rays[id], tfar, rh)) continue;
      // Reported as the entity's own geometry ID (as a directly attached
      // mesh), so finishHit fills the triangle's hit record.
      RTCRayN_tfar(rays, n, i) = rh.ray.tfar;
      setHit(hits, n, i, rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z, rh.hit.u, rh.hit.v,
             rh.hit.primID, ref.index, RTC_INVALID_GEOMETRY_ID);
    }
  }

  static void movingOccluded(const RTCOccludedFunctionNArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    const EmbreeAccelerator::ShapeRef &ref = self->movingRefs_[args->primID];
    const MovingBoxes *boxes = boxTestFor(*self, ref);
    if (!ref.entity->isMesh()) return occludedShapeLanes(args, ref, boxes);
    occludedLanes(args, kNoEntity, [&ref, boxes](const Ray &r, float tfar) {
      if (boxes && boxes->misses(ref.index, r, tfar)) return false;
      RTCRay o;
      toRay1(objectSpaceRay(*ref.entity, r), Vec3(), o);
      o.tfar = std::min(o.tfar, tfar);
      RTCIntersectContext inner;
      rtcInitIntersectContext(&inner);
      rtcOccluded1(ref.meshScene, &inner, &o);
      return o.tfar < 0;
    });
  }

  static void occluded(const RTCOccludedFunctionNArguments *args) {
    const auto *self = static_cast<const EmbreeAccelerator *>(args->geometryUserPtr);
    occludedShapeLanes(args, self->shapeRefs_[args->primID], nullptr);
  }

  /// As intersectShapeLanes, for any hit.
  static void occludedShapeLanes(const RTCOccludedFunctionNArguments *args,
                                 const EmbreeAccelerator::ShapeRef &shape,
                                 const MovingBoxes *moving) {
    if (shape.stillSphere) return occludedSphereLanes(args, shape);
    occludedLanes(args, shape.index, [&shape, moving](const Ray &ray, float tfar) {
      const double tMax = std::min(ray.tMax, static_cast<double>(tfar));
      if (moving && moving->misses(shape.index, ray, tMax)) return false;
      return occludedShape(*shape.entity, ray, tMax);
    });
  }

  /// occludedLanes for a still sphere: its bound (SphereBound) settles the
  /// lanes four at a time first; the rest take occludedStillSphere.
  static void occludedSphereLanes(const RTCOccludedFunctionNArguments *args,
                                  const EmbreeAccelerator::ShapeRef &shape) {
    auto *ctx = reinterpret_cast<QueryContext *>(args->context);
    const unsigned n = args->N;
    for (unsigned base = 0; base < n; base += 4) {
      // Lanes past N, invalid or occluded read the packet's first ray.
      const Ray *rays[4] = {ctx->rays, ctx->rays, ctx->rays, ctx->rays};
      uint32_t open = 0;
      for (unsigned k = 0; k < 4 && base + k < n; ++k) {
        const unsigned i = base + k;
        if (!args->valid[i] || RTCRayN_tfar(args->ray, n, i) < 0) continue;
        rays[k] = &ctx->rays[RTCRayN_id(args->ray, n, i)];
        open |= 1u << k;
      }
      if (open == 0) continue;
      if (n >= 4) open &= ~shape.sphereBound.missesLines(rays);
      for (; open != 0; open &= open - 1) {
        const unsigned k = static_cast<unsigned>(std::countr_zero(open));
        float &tfar = RTCRayN_tfar(args->ray, n, base + k);
        if (n < 4 && shape.sphereBound.missesLine(*rays[k])) continue;
        if (occludedStillSphere(*shape.entity, *rays[k],
                                std::min(rays[k]->tMax, static_cast<double>(tfar)))) {
          tfar = -kInfinityF;
          if (ctx->blockers) ctx->blockers[rays[k] - ctx->rays] = shape.index;
        }
      }
    }
  }

  /// Marks each valid lane not yet occluded whose ray (the caller's double
  /// ray, and Embree's tfar) `blocks` says is blocked, naming `blocker`
  /// (an analytic entity, or kNoEntity) as what blocked it.
  template <class Blocks>
  static void occludedLanes(const RTCOccludedFunctionNArguments *args, uint32_t blocker,
                            Blocks blocks) {
    auto *ctx = reinterpret_cast<QueryContext *>(args->context);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
      if (!args->valid[i]) continue;
      float &tfar = RTCRayN_tfar(args->ray, n, i);
      if (tfar < 0) continue; // already occluded
      const unsigned id = RTCRayN_id(args->ray, n, i);
      if (!blocks(ctx->rays[id], tfar)) continue;
      tfar = -kInfinityF;
      if (ctx->blockers) ctx->blockers[id] = blocker;
    }
  }
};

namespace {

/// The ID of what a hit reported by Embree struck. Geometry IDs: a mesh
/// instance or directly attached mesh has its entity's index, so an ID below
/// entities.size() is a mesh entity; the analytic user geometry has ID
/// entities.size(); a miss has RTC_INVALID_GEOMETRY_ID.
unsigned hitEntity(unsigned geomID, unsigned instID) {
  return instID != RTC_INVALID_GEOMETRY_ID ? instID : geomID;
}

/// After Embree: the Hit for a closest hit it reported (meshes through the
/// shared triangle code; analytic hits were written by the callback).
bool finishHit(const Scene &scene, const Vec3 &frame, unsigned geomID, unsigned instID,
               unsigned primID, float tfar, float u, float v, const Ray &ray, Hit &hit) {
  if (geomID == RTC_INVALID_GEOMETRY_ID) return false;
  unsigned entity = hitEntity(geomID, instID);
  if (entity < scene.entities.size())
    fillTriangleHit(scene.entities[entity], entity, primID, tfar, u, v, ray, frame, hit);
  return true;
}

} // namespace

EmbreeAccelerator::EmbreeAccelerator(const Scene &scene)
    : scene_(scene), unbounded_(scene), moving_(scene) {
  auto start = std::chrono::steady_clock::now();
  try {
    build();
  } catch (const std::bad_alloc &) {
    // Out of memory or threads inside Embree: releasing its objects then
    // ends the process from inside Embree (std::terminate), so they are
    // left to the process's exit, which the error leads to.
    throw;
  } catch (...) {
    release();
    throw;
  }
  stats_.buildSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeAccelerator::~EmbreeAccelerator() { release(); }

void EmbreeAccelerator::release() {
  for (RTCScene s : meshScenes_) rtcReleaseScene(s);
  meshScenes_.clear();
  if (root_) rtcReleaseScene(root_);
  root_ = nullptr;
  if (device_) rtcReleaseDevice(device_);
  device_ = nullptr;
}

void EmbreeAccelerator::build() {
  device_ = rtcNewDevice(nullptr);
  // Embree's device fails to start for want of memory (its thread pool and
  // allocators): say so, as any other allocation failure does.
  if (!device_) {
    if (rtcGetDeviceError(nullptr) == RTC_ERROR_OUT_OF_MEMORY) throw std::bad_alloc();
    throw std::runtime_error("Embree: cannot create a device");
  }
  rtcSetDeviceErrorFunction(device_, &EmbreeCallbacks::error, this);
  rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeCallbacks::memory, this);

  auto newScene = [this] {
    RTCScene s = rtcNewScene(device_);
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_MEDIUM);
    return s;
  };
  root_ = newScene();

  const auto &entities = scene_.entities;
  frameOrigin_ = floatFrameOrigin(scene_);
  const bool rebase = frameOrigin_ != Vec3(0, 0, 0);
  size_t ownedBytes = 0;
  // A padded float copy of `mesh`'s vertices, each placed by `place`
  // (double in, double out): Embree reads 16 bytes at each vertex, so the
  // buffer extends 4 bytes past the last Vec3f.
  auto paddedCopy = [&](const MeshData &mesh, auto place) {
    auto &buffer = paddedPositions_.emplace_back(mesh.positions.size() + 1);
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3 p = place(toVec3(mesh.positions[i]));
      buffer[i] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    }
    ownedBytes += buffer.size() * sizeof(Vec3f);
    return static_cast<const Vec3f *>(buffer.data());
  };
  auto triangleGeometryOver = [&](const MeshData &mesh, const Vec3f *positions) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions, 0,
                               sizeof(Vec3f), mesh.positions.size());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               mesh.triangleIndices.data(), 0, 3 * sizeof(uint32_t),
                               mesh.triangleIndices.size() / 3);
    rtcCommitGeometry(g);
    stats_.primitives += mesh.triangleIndices.size() / 3;
    return g;
  };
  // Triangle geometry over the MeshData's own buffers, or over a copy of
  // them relative to the float frame (`inFrame`: an untransformed mesh of a
  // scene far from the world origin).
  std::map<std::pair<const MeshData *, bool>, const Vec3f *> copies;
  auto triangleGeometry = [&](const MeshData &mesh, bool inFrame) {
    // Use the vector's spare capacity for the padding if it has some, else
    // copy once (the framed copy is made with the padding too).
    const Vec3f *positions = mesh.positions.data();
    if (inFrame || mesh.positions.capacity() == mesh.positions.size()) {
      const Vec3f *&copy = copies[{&mesh, inFrame}];
      const Vec3 origin = inFrame ? frameOrigin_ : Vec3(); // p - 0 is p exactly
      if (!copy) copy = paddedCopy(mesh, [&](const Vec3 &p) { return p - origin; });
      positions = copy;
    }
    return triangleGeometryOver(mesh, positions);
  };

  std::unordered_map<const MeshData *, size_t> uses;
  for (const Entity &e : entities)
    if (e.isMesh() && e.mesh && !e.mesh->triangles.empty()) ++uses[e.mesh.get()];

  size_t placedTriangles = 0; // copies placed so far
  std::unordered_map<const MeshData *, RTCScene> meshScene;
  // The triangle scene of `mesh` in object space, built once.
  auto meshSceneOf = [&](const MeshData &mesh) {
    RTCScene &ms = meshScene[&mesh];
    if (!ms) {
      ms = newScene();
      meshScenes_.push_back(ms);
      RTCGeometry g = triangleGeometry(mesh, false);
      rtcAttachGeometryByID(ms, g, 0);
      rtcReleaseGeometry(g);
      rtcCommitScene(ms);
    }
    return ms;
  };
  // A mesh whose vertices move: its own scene of one triangle geometry
  // with a vertex buffer per motion step (Embree blends them linearly).
  auto deformingScene = [&](const MeshMotion &motion) {
    const MeshData &first = *motion.steps[0];
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryTimeStepCount(g, static_cast<unsigned>(motion.steps.size()));
    for (size_t s = 0; s < motion.steps.size(); ++s) {
      // Padded for Embree's 16-byte read of the last vertex.
      const std::vector<Vec3f> &positions = motion.steps[s]->positions;
      auto &buffer = paddedPositions_.emplace_back(positions.size() + 1);
      std::copy(positions.begin(), positions.end(), buffer.begin());
      ownedBytes += buffer.size() * sizeof(Vec3f);
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, static_cast<unsigned>(s),
                                 RTC_FORMAT_FLOAT3, buffer.data(), 0, sizeof(Vec3f),
                                 positions.size());
    }
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               first.triangleIndices.data(), 0, 3 * sizeof(uint32_t),
                               first.triangleIndices.size() / 3);
    rtcCommitGeometry(g);
    stats_.primitives += first.triangleIndices.size() / 3;
    RTCScene ms = newScene();
    meshScenes_.push_back(ms);
    rtcAttachGeometryByID(ms, g, 0);
    rtcReleaseGeometry(g);
    rtcCommitScene(ms);
    return ms;
  };
  for (size_t i = 0; i < entities.size(); ++i) {
    const Entity &e = entities[i];
    auto id = static_cast<unsigned>(i);
    if (e.moves() && !UnboundedShapes::holds(e)) {
      if (!e.isMesh()) {
        if (!shapeWorldBounds(e).empty()) movingRefs_.push_back({&e, id});
      } else if (e.mesh && !e.mesh->triangles.empty()) {
        movingRefs_.push_back(
            {&e, id, e.vertexMotion ? deformingScene(*e.vertexMotion) : meshSceneOf(*e.mesh)});
        ++stats_.instances;
      }
      continue;
    }
    if (!e.isMesh()) {
      // A shape with empty bounds (a CSG Intersection of disjoint solids)
      // has nothing to hit, and Embree would take its inverted box in.
      if (!UnboundedShapes::holds(e) && !shapeWorldBounds(e).empty())
        shapeRefs_.push_back({&e, id, nullptr, isStillSphere(e),
                              isStillSphere(e) ? SphereBound(e.worldFromObject) : SphereBound()});
      continue;
    }
    if (!e.mesh || e.mesh->triangles.empty()) continue;
    const MeshData &mesh = *e.mesh;
    bool identity = e.worldFromObject.isIdentity();
    if (identity && (uses[&mesh] == 1 || rebase)) {
      // Sole, untransformed user of its mesh: no instance level to cross.
      // Far from the origin every untransformed user gets the framed copy
      // (an instance would move rays by the frame's offset in float).
      RTCGeometry g = triangleGeometry(mesh, rebase);
      rtcAttachGeometryByID(root_, g, id);
      rtcReleaseGeometry(g);
      continue;
    }
    if (placeable(mesh, uses[&mesh], placedTriangles)) {
      // Its triangles placed in the world, relative to the float frame.
      const Transform &place = e.worldFromObject;
      const Vec3f *placed =
          paddedCopy(mesh, [&](const Vec3 &p) { return place.applyPoint(p) - frameOrigin_; });
      RTCGeometry g = triangleGeometryOver(mesh, placed);
      rtcAttachGeometryByID(root_, g, id);
      rtcReleaseGeometry(g);
      continue;
    }
    RTCGeometry inst = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, meshSceneOf(mesh));
    // Translate(-frame origin) * worldFromObject, composed in double.
    const auto &m = e.worldFromObject.matrix().m;
    float xfm[12];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        xfm[4 * r + c] = static_cast<float>(c == 3 ? m[r][3] - frameOrigin_[r] : m[r][c]);
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
    rtcCommitGeometry(inst);
    rtcAttachGeometryByID(root_, inst, id);
    rtcReleaseGeometry(inst);
    ++stats_.instances;
  }

  if (!shapeRefs_.empty()) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(shapeRefs_.size()));
    rtcSetGeometryUserData(g, this);
    rtcSetGeometryBoundsFunction(g, &EmbreeCallbacks::bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, &EmbreeCallbacks::intersect);
    rtcSetGeometryOccludedFunction(g, &EmbreeCallbacks::occluded);
    rtcCommitGeometry(g);
    // An ID no mesh instance uses: the entity indices are taken.
    rtcAttachGeometryByID(root_, g, static_cast<unsigned>(entities.size()));
    rtcReleaseGeometry(g);
    stats_.primitives += shapeRefs_.size();
  }
  if (!movingRefs_.empty()) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryTimeStepCount(g, static_cast<unsigned>(scene_.motionSteps));
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(movingRefs_.size()));
    rtcSetGeometryUserData(g, this);
    rtcSetGeometryBoundsFunction(g, &EmbreeCallbacks::movingBounds, nullptr);
    rtcSetGeometryIntersectFunction(g, &EmbreeCallbacks::movingIntersect);
    rtcSetGeometryOccludedFunction(g, &EmbreeCallbacks::movingOccluded);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(root_, g, static_cast<unsigned>(entities.size() + 1));
    rtcReleaseGeometry(g);
    for (const ShapeRef &ref : movingRefs_)
      if (!ref.entity->isMesh()) ++stats_.primitives;
  }
  stats_.primitives += unbounded_.size();
  rtcCommitScene(root_);

  if (errorCode_.load() == RTC_ERROR_OUT_OF_MEMORY ||
      std::strstr(errorMessage_, "pthread_create") != nullptr)
    throw std::bad_alloc(); // reported as "out of memory"
  if (errorCode_.load() != 0)
    throw std::runtime_error("Embree error " + std::to_string(errorCode_.load()) + ": " +
                             std::string(errorMessage_));
  ownedBytes += (shapeRefs_.capacity() + movingRefs_.capacity()) * sizeof(ShapeRef);
  stats_.memoryBytes = static_cast<size_t>(std::max<std::ptrdiff_t>(0, embreeBytes_.load())) +
                       ownedBytes;
}

bool EmbreeAccelerator::intersect(const Ray &ray, Hit &hit) const {
  RTCRayHit rh;
  toRayHit1(ray, frameOrigin_, rh);
  double bestT = ray.tMax;
  QueryContext ctx;
  rtcInitIntersectContext(&ctx.base);
  ctx.rays = &ray;
  ctx.hits = &hit;
  ctx.bestT = &bestT;
  rtcIntersect1(root_, &ctx.base, &rh);
  bool found = finishHit(scene_, frameOrigin_, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID,
                         rh.ray.tfar, rh.hit.u, rh.hit.v, ray, hit);
  return unbounded_.empty() ? found : unbounded_.intersect(ray, hit, found);
}

bool EmbreeAccelerator::occluded(const Ray &ray) const {
  if (!unbounded_.empty() && unbounded_.occluded(ray)) return true;
  RTCRay r;
  toRay1(ray, frameOrigin_, r);
  QueryContext ctx;
  rtcInitIntersectContext(&ctx.base);
  ctx.rays = &ray;
  rtcOccluded1(root_, &ctx.base, &r);
  return r.tfar < 0;
}

void EmbreeAccelerator::intersectCoherent(const Ray *rays, size_t count, Hit *hits,
                                          uint8_t *found) const {
  // The mesh hit records read MeshData that Embree never touched (it keeps
  // its own vertex copies), two dependent cache misses per hit (corner
  // indices, then vertices). So the packets of a chunk (a renderer tile) are
  // traced first, through one reused packet: each packet's mesh hits are
  // recorded as fill queries with their corners prefetched, and their
  // vertices are prefetched after the next packet's trace. Then all the
  // chunk's mesh hits are filled in one batch, four to a SIMD group
  // (triangle_hits.cpp), groups no longer split at packet ends. On
  // bench_embree's 1M-triangle mesh this comes closer to raw Embree's
  // packets than filling each packet two traces after its own, in the same
  // loop (bench/HISTORY.md, figures from source comments). Analytic hits
  // are written by their callbacks during the trace.
  constexpr size_t kChunk = 32 * 8;
  TriangleHitQuery queries[kChunk];
  const std::vector<Entity> &entities = scene_.entities;
  auto prefetchVertices = [&](size_t first, size_t end) {
    for (size_t j = first; j < end; ++j)
      prefetchTriangleVertices(*queries[j].entity->mesh, queries[j].triangle);
  };
  alignas(32) RTCRayHit8 rh;
  for (size_t chunkBase = 0; chunkBase < count; chunkBase += kChunk) {
    const size_t chunkEnd = std::min(count, chunkBase + kChunk);
    size_t nq = 0, previous = 0;
    for (size_t base = chunkBase; base < chunkEnd; base += 8) {
      const size_t lanes = std::min<size_t>(8, chunkEnd - base);
      alignas(32) int valid[8];
      double bestT[8];
      toRayHit8(rays + base, lanes, frameOrigin_, rh, valid, bestT);
      QueryContext ctx;
      rtcInitIntersectContext(&ctx.base);
      ctx.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      ctx.rays = rays + base;
      ctx.hits = hits + base;
      ctx.bestT = bestT;
      rtcIntersect8(valid, root_, &ctx.base, &rh);
      const size_t first = nq;
      for (unsigned i = 0; i < lanes; ++i) {
        const size_t r = base + i;
        found[r] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        const unsigned id = hitEntity(rh.hit.geomID[i], rh.hit.instID[0][i]);
        if (id >= entities.size()) continue;
        queries[nq++] = {&entities[id], id, rh.hit.primID[i], rh.ray.tfar[i],
                         rh.hit.u[i], rh.hit.v[i], &rays[r], &hits[r]};
        prefetchTriangleCorners(*entities[id].mesh, rh.hit.primID[i]);
      }
      prefetchVertices(previous, first);
      previous = first;
    }
    prefetchVertices(previous, nq);
    fillTriangleHits(queries, nq, frameOrigin_);
  }
  if (!unbounded_.empty())
    for (size_t i = 0; i < count; ++i) found[i] = unbounded_.intersect(rays[i], hits[i], found[i]);
}

double EmbreeAccelerator::rawSeconds(const Ray *rays, size_t count, RawQuery query) const {
  std::vector<Hit> scratch(8);
  const auto start = std::chrono::steady_clock::now();
  const bool packets = query == RawQuery::ClosestPackets || query == RawQuery::OcclusionPackets;
  const bool closest = query == RawQuery::Closest || query == RawQuery::ClosestPackets;
  for (size_t base = 0; base < count; base += packets ? 8 : 1) {
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.rays = rays + base;
    ctx.hits = scratch.data();
    double bestT[8];
    ctx.bestT = bestT;
    if (!packets) {
      RTCRayHit rh;
      toRayHit1(rays[base], frameOrigin_, rh);
      bestT[0] = rays[base].tMax;
      if (closest) rtcIntersect1(root_, &ctx.base, &rh);
      else rtcOccluded1(root_, &ctx.base, &rh.ray);
      continue;
    }
    // As the renderer calls them (occludedCoherent: shadow packets as
    // incoherent).
    ctx.base.flags =
        closest ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    const size_t lanes = std::min<size_t>(8, count - base);
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    toRayHit8(rays + base, lanes, frameOrigin_, rh, valid, bestT);
    if (closest) rtcIntersect8(valid, root_, &ctx.base, &rh);
    else rtcOccluded8(valid, root_, &ctx.base, &rh.ray);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeAccelerator::occludedCoherent(const Ray *rays, size_t count, uint8_t *occluded,
                                         uint32_t *blockers) const {
  if (blockers) std::fill_n(blockers, count, kNoEntity);
  for (size_t base = 0; base < count; base += 8) {
    size_t lanes = std::min<size_t>(8, count - base);
    alignas(32) int valid[8];
    alignas(32) RTCRay8 r8;
    toRay8(rays + base, lanes, frameOrigin_, r8, valid);
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.base);
    // Neighbouring points' shadow rays, but told to Embree as incoherent:
    // measured so, its traversal of them is faster (the 2011 texture and
    // finish examples -10 %, mesh200k with an area light -22 %; each ray's
    // answer the same), while camera packets are faster told coherent
    // (intersectCoherent). Shadow rays to an area light's jittered points
    // part where they pass a mesh's edges, unlike a camera's.
    ctx.base.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    ctx.rays = rays + base;
    ctx.blockers = blockers ? blockers + base : nullptr;
    rtcOccluded8(valid, root_, &ctx.base, &r8);
    for (unsigned i = 0; i < lanes; ++i) occluded[base + i] = r8.tfar[i] < 0 ? 1 : 0;
  }
  if (!unbounded_.empty())
    for (size_t i = 0; i < count; ++i)
      if (!occluded[i]) occluded[i] = unbounded_.occluded(rays[i]);
}

} // namespace lray
