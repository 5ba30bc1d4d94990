// Pipeline: scene description. The plain C++ model a frame's Lua scene is
// converted into; everything below this (backends, shading, rendering) reads
// only these types and never touches Lua.
#pragma once

#include "geometry/shapes/shape_list.h"
#include "math/color.h"
#include "math/transform.h"
#include "math/transform_motion.h"
#include "math/vec3.h"
#include "scene/mesh_data.h"
#include "scene/mesh_motion.h"
#include "shading/lights/light_list.h"
#include "shading/pigments/pigment_list.h"
#include "shading/pigments/texture_map.h"
#include "util/memory_budget.h"
#include "util/scene_error.h"
#include "shading/pigments/texture_map.h"
#include "shading/pigments/pigment_list.h"
#include "shading/lights/light_list.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lray {

/// SceneInfo: image size and animation (lua/README.md, "Scene and camera").
struct SceneInfo {
  int imageWidth = 800;
  int imageHeight = 600;
  int frames = 1;
  int samples = 1; ///< n: an n x n grid of samples per pixel
  double noiseThreshold = 0; ///< > 0: adaptive sampling to this error estimate
  std::string integrator = "whitted"; ///< "whitted" or "path" (lua/README.md, "Light transport")
  int maxDepth = 8; ///< path: the most scattering events of a path
  double startClock = 0;
  double endClock = 1;
  /// Motion blur (lua/README.md, "Motion blur"): the fraction of the
  /// interval between two frames' clocks the shutter stays open, from the
  /// frame's clock on (0: no blur), and how many clock values in that
  /// interval scene(clock) is called at.
  double shutter = 0;
  int motionSteps = 2;

  /// The clock interval between frame i and the next: the whole clock
  /// range for a single frame.
  double frameInterval() const {
    const double span = endClock - startClock;
    return frames <= 1 ? span : span / (frames - 1);
  }

  /// Clock value for 0-based frame i (lua/README.md, "The scene file"):
  /// finite for any finite clocks, even where their difference is not.
  double clockForFrame(int i) const {
    if (frames <= 1) return startClock;
    const double span = endClock - startClock;
    if (std::isfinite(span)) return startClock + span * i / (frames - 1);
    const double t = static_cast<double>(i) / (frames - 1);
    return startClock * (1 - t) + endClock * t;
  }
};

/// Finish (lua/README.md, "Textures, finishes and pigments"), with its defaults.
struct Finish {
  Color ambient{0.02, 0.02, 0.02};
  double diffuse = 0.6;
  double specular = 0.1;
  double exponent = 1.0;
  double reflection = 0;
  double refraction = 0;
  double refractionIndex = 1.0;
  double absorption = 0.5;
  /// Radiance leaving the surface on the side its normal points to.
  Color emission{0, 0, 0};
  /// Reflection and refraction weights times the dielectric Fresnel
  /// reflectance F and 1 - F of refractionIndex.
  bool fresnel = false;
  /// GGX alpha of the reflection and refraction lobes, in [0, 1]; 0: a
  /// perfect mirror and refraction (shading/specular_lobes.h).
  double roughness = 0;
};

/// A pigment (lua/README.md, "Textures, finishes and pigments"): one of shading/pigments/ with its
/// parameters, the texture map that gives it its lookup point, and where it was defined. Checkers
/// refer to their two sub-pigments by index into Scene::pigments (always smaller indices: the table
/// is built bottom-up).
struct Pigment {
  PigmentPattern pattern;
  TextureMap map;
  SourceLocation loc;
};

/// An image used by ImagePigment2D, named by absolute path (resolved against
/// the scene file's folder by the scene layer). Loaded by the shading layer.
struct ImageRef {
  std::string path;
  SourceLocation loc;
};

/// Texture = finish + pigment (index into Scene::pigments).
struct Texture {
  Finish finish;
  uint32_t pigment = 0;
  SourceLocation loc; ///< none for the default texture
};

/// An entity placed in the world (lua/README.md, "Entities"): a shape of geometry/shapes/ with
/// its parameters. For meshes, `mesh` holds the (possibly shared) geometry
/// and `worldFromObject` the mesh transform.
struct Entity {
  Shape shape;
  Transform worldFromObject;
  bool smooth = false; ///< Mesh: interpolate vertex normals
  /// Whether its texture may read the surface's (u, v): false for a plain
  /// colour, when an analytic shape's hit may leave them out (a sphere's
  /// angle around its axis costs an atan2).
  bool readsUv = true;
  uint32_t texture = 0; ///< index into Scene::textures
  MeshDataPtr mesh;     ///< Mesh only
  SourceLocation loc;
  /// Set when the entity moves while the shutter is open: worldFromObject
  /// at each motion step (worldFromObject itself is step 0's). Every ray
  /// meets the entity where it is at the ray's time.
  std::shared_ptr<const TransformMotion> motion;
  /// Set when a Mesh's vertices move while the shutter is open.
  std::shared_ptr<const MeshMotion> vertexMotion;

  /// Whether anything about it moves while the shutter is open.
  bool moves() const { return motion || vertexMotion; }
  /// The placement at shutter time `time` (Ray::time).
  Transform placementAt(double time) const { return motion ? motion->at(time) : worldFromObject; }

  ShapeKind kind() const { return static_cast<ShapeKind>(shape.index()); }
  bool isMesh() const { return std::holds_alternative<Mesh>(shape); }
};

/// No entity: an index past any scene's (Scene::entities).
inline constexpr uint32_t kNoEntity = UINT32_MAX;

/// The kinds of camera (lua/README.md, "Perspective", "Orthographic",
/// "Spherical").
enum class CameraKind { Perspective, Orthographic, Spherical };

/// The camera: it looks down +z of its own frame, +y up. Perspective: the
/// horizontal fov in degrees, aspect = w/h of the image plane, and a thin
/// lens of radius `aperture` (0: a pinhole) focused at `focalDistance`
/// along the view axis. Orthographic: parallel rays over a view `width`
/// units wide (and width / aspect high). Spherical: every direction,
/// longitude across the image and latitude down it.
struct Camera {
  CameraKind kind = CameraKind::Perspective;
  double fov = 45;
  double aspect = 1.33;
  double width = 2;
  double aperture = 0;
  double focalDistance = 1;
  Transform worldFromCamera;
  SourceLocation loc;
  /// Set when the camera moves while the shutter is open (as Entity::motion).
  std::shared_ptr<const TransformMotion> motion;
};

/// One frame's complete scene.
struct Scene {
  Color background{0, 0, 0};
  Camera camera;
  std::vector<Entity> entities;
  std::vector<SceneLight> lights; ///< shading/lights/light_list.h
  /// Per light, parallel to `lights` (or empty when none moves): its
  /// motion, or none.
  std::vector<std::shared_ptr<const LightMotion>> lightMotion;
  /// Motion steps of the frame's shutter (0: no motion blur; rays keep
  /// time 0).
  int motionSteps = 0;
  std::vector<Texture> textures; ///< at least one (the default) when entities exist
  std::vector<Pigment> pigments;
  std::vector<ImageRef> images;
  /// What this frame has been charged against --render-memory so far (the
  /// model by the converter; textures and the acceleration structure add
  /// theirs before they are allocated). A SceneScript's frames carry its
  /// --render-memory (ScriptOptions::renderMemoryBytes); else no limit.
  MemoryBudget memory;
};

} // namespace lray
