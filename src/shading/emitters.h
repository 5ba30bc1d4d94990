// Pipeline: shading. The scene's emitting surfaces as light sources the
// path tracer samples directly (next-event estimation, lua/README.md,
// "Light transport"): a Sphere, Cube, Cylinder, Cone, ring Torus or Mesh
// entity whose finish emits. One is chosen by its power (emission's mean
// times its area), then a point on it uniformly by its object-space area
// (exactly by world area for triangles). pdfArea gives the same density for
// a point a path found by itself, for multiple importance sampling.
// Emitting CSG leaves and spindle tori are not sampled: paths find them by
// bouncing.
#pragma once

#include "math/color.h"
#include "math/hit.h"
#include "math/random.h"
#include "math/vec3.h"
#include "scene/scene.h"

#include <cstdint>
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
  /// A point on one of the emitters (three numbers of `sampler`).
  Sample sample(Sampler &sampler) const;

  /// The density per unit world area with which sample() gives the point
  /// of `hit` (0 for a surface it does not sample).
  double pdfArea(const Hit &hit) const;

private:
  enum class Kind : uint8_t { Sphere, Cube, Cylinder, Cone, Torus, Triangle };
  struct Entry {
    uint32_t entity;
    uint32_t triangle; ///< Triangle: its index in the mesh
    Kind kind;
    double probability; ///< of choosing this entry
    double area;        ///< Triangle: world area; else object-space area
  };
  /// A point and its outward object-space normal on a cylinder or cone,
  /// uniform by object-space area, from two uniform numbers.
  void sampleRound(const Entry &entry, double u, double v, Vec3 &p, Vec3 &n) const;
  /// The same on a ring torus (major > minor).
  static void sampleTorus(const Torus &t, double u, double v, Vec3 &p, Vec3 &n);
  /// Object-space area over world area at a point of world normal n
  /// (unit) on an affinely placed surface.
  double worldAreaFactor(const Entity &e, const Vec3 &n) const;

  const Scene &scene_;
  std::vector<Entry> entries_;
  std::vector<double> cumulative_;  ///< of the entries' probabilities
  std::vector<int64_t> firstEntry_; ///< per entity: its first entry, or -1
};

} // namespace lray
