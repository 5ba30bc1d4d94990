// Fuzz target (libFuzzer): scene -> backend -> tiny render. The input bytes
// describe a small scene (analytic shapes and meshes, including degenerate
// triangles, under transforms from 1e-4 to 1e4 in scale and up to 1e5 in
// offset, random finishes, point and area lights, a camera anywhere) that
// is rendered at 4x4 with both backends. CSG entities get random nested
// trees (every operator, every solid, planes, coincident placements, open
// cylinders the converter would refuse) with textures per solid. A crash, a
// sanitizer report or a non-finite sample (RayCounts::nonFinite > 0) is a bug.
#include "render/backends.h"
#include "geometry/csg_tree.h"
#include "render/renderer.h"
#include "scene/mesh_builder.h"
#include "shading/image_cache.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace {

using lray::Transform;
using lray::Vec3;

double magnitude(FuzzedDataProvider &in) {
  static const double kMagnitudes[] = {0, 1e-4, 1e-2, 0.5, 1, 2, 10, 1e2, 1e4, 1e5};
  double m = kMagnitudes[in.ConsumeIntegralInRange<size_t>(0, 9)];
  return in.ConsumeBool() ? -m : m;
}

Vec3 vec(FuzzedDataProvider &in, double range) {
  return {in.ConsumeFloatingPointInRange(-range, range),
          in.ConsumeFloatingPointInRange(-range, range),
          in.ConsumeFloatingPointInRange(-range, range)};
}

Transform transform(FuzzedDataProvider &in) {
  Transform t;
  int steps = in.ConsumeIntegralInRange(0, 3);
  for (int i = 0; i < steps; ++i) {
    Transform s;
    switch (in.ConsumeIntegralInRange(0, 2)) {
    case 0: s = Transform::translate({magnitude(in), magnitude(in), magnitude(in)}); break;
    case 1: {
      double sx = std::fabs(magnitude(in)), sy = std::fabs(magnitude(in)),
             sz = std::fabs(magnitude(in));
      s = Transform::scale(sx > 0 ? sx : 1, sy > 0 ? sy : 1, sz > 0 ? sz : 1);
      break;
    }
    default:
      s = Transform::rotate(vec(in, 1), in.ConsumeFloatingPointInRange(-360.0, 360.0));
      break;
    }
    if (!s.singular()) t = s * t;
  }
  return t;
}

lray::MeshDataPtr mesh(FuzzedDataProvider &in) {
  lray::MeshSource src;
  int nv = in.ConsumeIntegralInRange(3, 8);
  double range = std::fabs(magnitude(in)) + 1;
  for (int i = 0; i < nv; ++i) {
    Vec3 p = vec(in, range);
    // Some vertices repeated exactly: zero-area and sliver triangles.
    if (i > 0 && in.ConsumeIntegralInRange(0, 3) == 0)
      p = {src.positions[i - 1].x, src.positions[i - 1].y, src.positions[i - 1].z};
    src.positions.push_back({float(p.x), float(p.y), float(p.z)});
  }
  if (in.ConsumeBool()) src.normals.push_back({0, 0, in.ConsumeBool() ? 1.f : 0.f});
  int nf = in.ConsumeIntegralInRange(1, 6);
  for (int f = 0; f < nf; ++f) {
    int corners = in.ConsumeIntegralInRange(3, 4);
    for (int c = 0; c < corners; ++c) {
      lray::MeshCorner k;
      k.v = in.ConsumeIntegralInRange(0, nv - 1);
      if (!src.normals.empty() && in.ConsumeBool()) k.n = 0;
      src.corners.push_back(k);
    }
    src.faceSizes.push_back(static_cast<uint32_t>(corners));
  }
  return lray::buildMeshData(src);
}

/// A random solid (any analytic shape but CSG) placed by a random transform.
lray::Entity solid(FuzzedDataProvider &in, uint32_t textures) {
  static const lray::ShapeKind kSolids[] = {lray::ShapeKind::Sphere, lray::ShapeKind::Cylinder,
                                            lray::ShapeKind::Cone,   lray::ShapeKind::Cube,
                                            lray::ShapeKind::Plane,  lray::ShapeKind::Torus};
  lray::Entity e;
  e.shape = lray::makeShape(kSolids[in.ConsumeIntegralInRange<size_t>(0, 5)]);
  // Often the identity or a small step: solids sharing faces and centres.
  e.worldFromObject = in.ConsumeBool() ? Transform() : transform(in);
  bool open = in.ConsumeIntegralInRange(0, 7) == 0;
  if (auto *c = std::get_if<lray::Cylinder>(&e.shape)) c->open = open;
  if (auto *c = std::get_if<lray::Cone>(&e.shape)) c->open = open;
  if (auto *t = std::get_if<lray::Torus>(&e.shape)) {
    t->major = in.ConsumeFloatingPointInRange(0.01, 4.0);
    t->minor = in.ConsumeFloatingPointInRange(0.01, 4.0);
  }
  e.texture = in.ConsumeIntegralInRange<uint32_t>(0, textures);
  return e;
}

void csgChildren(FuzzedDataProvider &in, lray::CsgTree &tree, uint32_t node, const Transform &world,
                 int depth, uint32_t textures) {
  int n = in.ConsumeIntegralInRange(1, 4);
  // At least one child each (as the bindings require); about 24 solids at most.
  for (int i = 0; i < n && (i == 0 || tree.leaves.size() < 24); ++i) {
    if (depth < 3 && in.ConsumeIntegralInRange(0, 3) == 0) {
      uint32_t sub = tree.addNode(static_cast<lray::CsgOp>(in.ConsumeIntegralInRange(0, 3)), node);
      Transform t = world * transform(in);
      csgChildren(in, tree, sub, t.singular() ? world : t, depth + 1, textures);
      continue;
    }
    lray::Entity e = solid(in, textures);
    Transform t = world * e.worldFromObject;
    if (!t.singular()) e.worldFromObject = t;
    uint32_t leaf = tree.addLeaf(std::move(e), node);
    if (in.ConsumeBool()) {
      tree.leaves[leaf].inheritsTexture = true;
      tree.leaves[leaf].textureSpace = world;
    }
  }
}

lray::Shape csg(FuzzedDataProvider &in, uint32_t textures) {
  auto tree = std::make_shared<lray::CsgTree>();
  tree->addNode(static_cast<lray::CsgOp>(in.ConsumeIntegralInRange(0, 3)),
                lray::CsgTree::kNoParent);
  csgChildren(in, *tree, 0, transform(in), 0, textures);
  tree->finish();
  return lray::Csg{std::move(tree)};
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FuzzedDataProvider in(data, size);
  lray::Scene scene;
  scene.pigments = {lray::Pigment{}};
  int textures = in.ConsumeIntegralInRange(1, 3);
  for (int i = 0; i < textures; ++i) {
    lray::Texture t;
    t.finish.diffuse = in.ConsumeFloatingPointInRange(-1.0, 2.0);
    t.finish.specular = in.ConsumeFloatingPointInRange(-1.0, 2.0);
    t.finish.exponent = in.ConsumeFloatingPointInRange(0.0, 1e4);
    t.finish.reflection = in.ConsumeFloatingPointInRange(0.0, 1.0);
    t.finish.refraction = in.ConsumeFloatingPointInRange(0.0, 1.0);
    t.finish.refractionIndex = in.ConsumeFloatingPointInRange(0.0, 10.0);
    t.finish.absorption = in.ConsumeFloatingPointInRange(-1.0, 10.0);
    scene.textures.push_back(t);
  }
  int entities = in.ConsumeIntegralInRange(1, 6);
  for (int i = 0; i < entities; ++i) {
    lray::Entity e;
    e.shape = lray::makeShape(static_cast<lray::ShapeKind>(
        in.ConsumeIntegralInRange<int>(0, std::variant_size_v<lray::Shape> - 1)));
    e.worldFromObject = transform(in);
    bool open = in.ConsumeBool();
    if (auto *c = std::get_if<lray::Cylinder>(&e.shape)) c->open = open;
    if (auto *c = std::get_if<lray::Cone>(&e.shape)) c->open = open;
    if (auto *t = std::get_if<lray::Torus>(&e.shape)) {
      t->major = in.ConsumeFloatingPointInRange(0.01, 4.0);
      t->minor = in.ConsumeFloatingPointInRange(0.01, 4.0);
    }
    e.smooth = in.ConsumeBool();
    e.texture = in.ConsumeIntegralInRange<uint32_t>(0, static_cast<uint32_t>(textures));
    if (e.kind() == lray::ShapeKind::Csg) e.shape = csg(in, static_cast<uint32_t>(textures));
    if (e.kind() == lray::ShapeKind::Mesh) {
      try {
        e.mesh = mesh(in);
      } catch (const lray::SceneError &) {
        continue;
      }
    }
    scene.entities.push_back(e);
  }
  int lights = in.ConsumeIntegralInRange(0, 2);
  for (int i = 0; i < lights; ++i) {
    if (in.ConsumeBool()) {
      lray::SpotLight l;
      l.angle = in.ConsumeFloatingPointInRange(0.0, 90.0);
      l.falloff = in.ConsumeFloatingPointInRange(l.angle, 90.0);
      l.worldFromLight = transform(in);
      scene.lights.push_back(l);
      continue;
    }
    lray::Light l;
    l.area = in.ConsumeBool();
    l.rows = in.ConsumeIntegralInRange(1, 3);
    l.cols = in.ConsumeIntegralInRange(1, 3);
    l.worldFromLight = transform(in);
    scene.lights.push_back(l);
  }
  scene.camera.fov = in.ConsumeFloatingPointInRange(1.0, 179.0);
  scene.camera.aspect = in.ConsumeFloatingPointInRange(0.1, 10.0);
  Vec3 eye = vec(in, std::fabs(magnitude(in)) + 1), at = vec(in, 5);
  Transform look = Transform::lookAt(eye, at, {0, 1, 0});
  if (!look.singular()) scene.camera.worldFromCamera = look;

  lray::ImageCache images(false);
  lray::FrameSettings fs;
  // 4x4 pixels: a few dozen camera rays reach every code path, and inputs
  // whose finishes keep full-weight reflection and refraction down to the
  // depth limit (2^16 rays a sample, legitimately) stay affordable.
  fs.width = 4;
  fs.height = 4;
  fs.samples = in.ConsumeIntegralInRange(1, 2);
  for (lray::BackendKind kind : {lray::BackendKind::Embree, lray::BackendKind::KdTree}) {
    auto accel = lray::makeAccelerator(kind, scene);
    lray::RayCounts counts;
    lray::Film film = lray::renderFrame(scene, *accel, images, fs, counts);
    if (counts.nonFinite != 0) std::abort();
  }
  return 0;
}
