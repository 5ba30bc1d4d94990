// Pipeline: shading. The scene's emitting surfaces as light sources the
// path tracer samples directly (next-event estimation, lua/README.md,
// "Light transport"): a Sphere, Cube, Cylinder, Cone, Torus or Mesh
// entity whose finish emits, and the emitting leaves of those kinds of a
// CSG entity. One is chosen by its power (emission's mean times its area),
// then a point on it uniformly by its object-space area (exactly by world
// area for triangles). A CSG leaf's point counts only where it is a surface
// of the result (the others are drawn and rejected: density 0). pdfArea
// gives the same density for a point a path found by itself, for multiple
// importance sampling. A moving emitter (lua/README.md, "Motion blur") is
// sampled where it is at the time of the path's camera sample (Hit::time).
#pragma once

#include "geometry/shape.h"
#include "math/color.h"
#include "math/hit.h"
#include "math/random.h"
#include "math/vec3.h"
#include "scene/scene.h"

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace lray {

class Emitters {
public:
  explicit Emitters(const Scene &scene);

  bool empty() const { return entries_.empty(); }

  struct Sample {
    Vec3 p;         ///< world point on the emitter
    Vec3 n;         ///< its unit geometric normal (the emitting side), as a hit there has it
    Color radiance; ///< the finish's emission
    double pdfArea; ///< density per unit world area, the emitter's choice included
  };
  /// A point on one of the emitters, placed as at shutter time `time`, to
  /// light `ref` (three numbers of `sampler`); pdfArea is 0 for a point of
  /// a CSG leaf that the result does not show. A sphere seen from outside
  /// is sampled by the solid angle it fills at `ref` (its visible cap
  /// only), any other emitter by area.
  Sample sample(const Vec3 &ref, float time, Sampler &sampler) const;

  /// The density per unit world area with which sample(ref, hit.time)
  /// gives the point of `hit` (0 for a surface it does not sample).
  double pdfArea(const Hit &hit, const Vec3 &ref) const;

private:
  enum class Kind : uint8_t { Sphere, Cube, Cylinder, Cone, Torus, Triangle };
  struct Entry {
    uint32_t entity;
    uint32_t part; ///< Triangle: its index in the mesh; a CSG leaf: its index in the tree
    Kind kind;
    bool csgLeaf;       ///< a leaf of the CSG entity `entity`, placed by its own transform
    double probability; ///< of choosing this entry
    double area;        ///< Triangle: world area (at step 0 if it moves); else object-space area
    bool moves = false; ///< its placement or vertices change over the shutter
    /// A Sphere placed without shear or uneven scale (at every motion step
    /// if it moves, and then in between): a world sphere.
    bool round = false;
    /// Triangle: its index in fixedTriangles_ when it does not move, else -1.
    int32_t fixedTriangle = -1;
  };
  /// A round sphere entry's world centre and radius at a time.
  struct Ball {
    Vec3 centre;
    double radius = 0;
  };
  /// The entity whose shape and placement an entry samples: the entity, or
  /// the CSG leaf's.
  const Entity &shapeOf(const Entry &entry) const;
  /// An entry for an analytic solid (kind and object-space area), or none.
  static std::optional<std::pair<Kind, double>> solidKind(const Entity &e);
  /// Whether placement `t` keeps a sphere a sphere (equal, orthogonal
  /// axes: a rotation, a uniform scale, a translation).
  static bool keepsRound(const Transform &t);
  /// A round sphere entry's ball at `time`.
  Ball ballAt(const Entry &entry, float time) const;
  /// Solid-angle sampling of a round sphere from `ref` outside it: the
  /// cone's half-angle term 1 - cos(theta_max), or 0 where `ref` is inside
  /// (then the sphere is sampled by area).
  static double coneSize(const Ball &ball, const Vec3 &ref);
  /// The density per unit area that uniform sampling of that cone gives a
  /// point p of normal n on the sphere (the solid angle's 1 / (2 pi cone)
  /// carried to area), the entry's choice included.
  static double conePdfArea(const Entry &entry, double cone, const Vec3 &ref, const Vec3 &p,
                            const Vec3 &n);
  /// A triangle entry's world area at `time`.
  double triangleArea(const Entry &entry, float time) const;
  /// Whether a point of CSG leaf `entry` (world p, normal n out of the
  /// leaf's solid) is a surface of the result; fills the result's normal.
  bool onCsgSurface(const Entry &entry, const Vec3 &p, float time, Vec3 &n) const;
  /// A point and its outward object-space normal on a cylinder or cone,
  /// uniform by object-space area, from two uniform numbers.
  void sampleRound(const Entry &entry, double u, double v, Vec3 &p, Vec3 &n) const;
  /// The same on a torus: a ring torus's whole tube, a spindle torus's
  /// apple-shaped surface.
  static void sampleTorus(const Torus &t, double u, double v, Vec3 &p, Vec3 &n);
  /// Object-space area over world area at a point of world normal n
  /// (unit) on a surface placed by `placement`.
  static double worldAreaFactor(const Transform &placement, const Vec3 &n);

  const Scene &scene_;
  std::vector<Entry> entries_;
  std::vector<FixedTriangle> fixedTriangles_;
  std::vector<double> cumulative_;  ///< of the entries' probabilities
  std::vector<int64_t> firstEntry_; ///< per entity: its first entry, or -1
};

} // namespace lray
