// Pipeline: geometry. Rays against a CSG entity (shapes/csg.h), called by
// shape.cpp for both backends.
//
// Each leaf lists the stretches of the ray's whole line inside it (its
// shape's spans), so the state at the ray's start is known even when it
// starts inside the result (a ray refracted into a CSG lens). The entries and
// exits are swept in order along the line; a crossing is a surface of the
// result when every operator above the leaf keeps it, judged from the other
// children's inside states at that point (POV-Ray's rules: a Union keeps
// every child's surface, a Merge and a Difference's base those outside the
// other children, an Intersection those inside all the others, a Difference
// the subtracted surfaces inside its base and outside the other subtracted
// ones).
//
// Coincident surfaces: crossings whose parameters differ by less than a
// relative 2^-32 of the ray's scale (far more than the rounding of the
// leaves' own tests) are one event; such a group is a surface when the
// result's inside state changes across it, or when one of its crossings is
// kept whatever the order of the others. So a cube minus a cube sharing a
// face has no surface on that face, and two unioned cubes sharing a face
// show it once: never speckles, and the same bits on both backends and any
// thread count (each ray's answer depends on that ray alone).
#pragma once

#include "math/hit.h"
#include "geometry/shapes/csg.h"
#include "math/ray.h"

#include <cstdint>

namespace lray {

/// The closest surface of the CSG result with t in (ray.tMin, ray.tMax):
/// fills `hit` as the leaf's own intersectShape would (its uv, texture
/// point and error bound), with entity = entityIndex, primitive = the
/// leaf's index in the tree, and the normal facing out of the result.
bool intersectCsg(const Csg &csg, uint32_t entityIndex, const Ray &ray, Hit &hit);

/// Whether any surface of the result lies in (ray.tMin, ray.tMax).
bool occludedCsg(const Csg &csg, const Ray &ray);

} // namespace lray
