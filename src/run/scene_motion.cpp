// Pipeline: run. Folding a frame's motion steps into one
// scene (scene_motion.h).
#include "run/scene_motion.h"

#include "geometry/csg_tree.h"
#include "geometry/shape.h"

#include <fmt/format.h>

#include <cmath>
#include <variant>

namespace lray {

namespace {

/// "entity 3 (scene.lua:12)": how messages name the i-th entity added.
std::string entityName(const Entity &e, size_t i) {
  const std::string where = e.loc.str();
  return fmt::format("entity {} ({}{}{})", i + 1, shapeName(e.shape), where.empty() ? "" : ", ",
                     where);
}

std::string lightName(const SceneLight &light, size_t i) {
  return std::visit(
      [&](const auto &l) {
        const std::string where = l.loc.str();
        return fmt::format("light {} ({}{}{})", i + 1, std::decay_t<decltype(l)>::kName,
                           where.empty() ? "" : ", ", where);
      },
      light);
}

bool same(const std::vector<Vec3f> &a, const std::vector<Vec3f> &b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
  return true;
}

/// Whether two meshes have the same triangles (corners, uv and normal
/// indices), so that only their vertices and normals may differ.
bool sameTriangles(const MeshData &a, const MeshData &b) {
  if (a.triangleIndices != b.triangleIndices || a.positions.size() != b.positions.size() ||
      a.normals.size() != b.normals.size() || a.triangles.size() != b.triangles.size())
    return false;
  for (size_t i = 0; i < a.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (a.triangles[i].uv[k] != b.triangles[i].uv[k] ||
          a.triangles[i].n[k] != b.triangles[i].n[k])
        return false;
  return true;
}

bool sameVertices(const MeshData &a, const MeshData &b) {
  return &a == &b || (same(a.positions, b.positions) && same(a.normals, b.normals));
}

/// Why `b`'s shape cannot be interpolated from `a`'s ("" when it can: the
/// same parameters, only the placement may differ).
std::string shapeChange(const Entity &a, const Entity &b) {
  if (a.kind() != b.kind()) return fmt::format("is a {} there", shapeName(b.shape));
  if (const auto *ta = std::get_if<Torus>(&a.shape)) {
    const auto &tb = std::get<Torus>(b.shape);
    if (ta->major != tb.major || ta->minor != tb.minor)
      return "changes its radii (radii are not interpolated: scale it with a transform)";
  }
  if (const auto *ca = std::get_if<Cylinder>(&a.shape))
    if (ca->open != std::get<Cylinder>(b.shape).open) return "changes 'open'";
  if (const auto *ca = std::get_if<Cone>(&a.shape))
    if (ca->open != std::get<Cone>(b.shape).open) return "changes 'open'";
  if (a.isMesh()) {
    const bool emptyA = !a.mesh || a.mesh->triangles.empty();
    const bool emptyB = !b.mesh || b.mesh->triangles.empty();
    if (emptyA != emptyB || (!emptyA && &*a.mesh != &*b.mesh && !sameTriangles(*a.mesh, *b.mesh)))
      return "changes its triangles (a moving mesh keeps its triangles; only its vertices "
             "and normals may move)";
  }
  if (const auto *csgA = std::get_if<Csg>(&a.shape)) {
    const auto &treeA = csgA->tree, &treeB = std::get<Csg>(b.shape).tree;
    if (!treeA || !treeB) return treeA == treeB ? "" : "changes its parts";
    if (treeA->leaves.size() != treeB->leaves.size() ||
        treeA->nodes.size() != treeB->nodes.size())
      return "changes its parts";
    for (size_t i = 0; i < treeA->leaves.size(); ++i) {
      const std::string change = shapeChange(treeA->leaves[i].entity, treeB->leaves[i].entity);
      if (!change.empty()) return "changes its parts: part " + std::to_string(i + 1) + " " + change;
    }
  }
  return "";
}

Vec3 lightPosition(const SceneLight &light) {
  return std::visit([](const auto &l) { return l.worldFromLight.applyPoint({0, 0, 0}); }, light);
}

} // namespace

std::vector<double> motionClocks(const SceneInfo &info, int frame) {
  const double clock = info.clockForFrame(frame);
  const double open = info.shutter * info.frameInterval();
  if (!(info.shutter > 0) || info.motionSteps < 2 || !(std::fabs(open) > 0) || !std::isfinite(open))
    return {clock};
  std::vector<double> clocks;
  const int k = info.motionSteps;
  for (int j = 0; j < k; ++j)
    clocks.push_back(j == 0 ? clock : clock + open * j / (k - 1));
  return clocks;
}

Scene foldMotionSteps(std::vector<Scene> steps, const std::vector<double> &clocks) {
  Scene scene = std::move(steps.at(0));
  const size_t k = steps.size();
  if (k < 2) return scene;
  auto mismatch = [&](size_t step, const std::string &what) {
    return SceneError(fmt::format(
        "motion blur: scene(clock) at clock {} and at clock {} do not match: {} (the scenes of "
        "one shutter are matched entity by entity and light by light, in the order they are "
        "added)",
        clocks[0], clocks[step], what));
  };
  for (size_t s = 1; s < k; ++s) {
    const Scene &other = steps[s];
    if (other.entities.size() != scene.entities.size())
      throw mismatch(
          s, fmt::format("{} entities, then {}", scene.entities.size(), other.entities.size()));
    if (other.lights.size() != scene.lights.size())
      throw mismatch(s,
                     fmt::format("{} lights, then {}", scene.lights.size(), other.lights.size()));
    for (size_t i = 0; i < scene.entities.size(); ++i) {
      const std::string change = shapeChange(scene.entities[i], other.entities[i]);
      if (!change.empty()) throw mismatch(s, entityName(scene.entities[i], i) + " " + change);
    }
    for (size_t i = 0; i < scene.lights.size(); ++i)
      if (scene.lights[i].index() != other.lights[i].index())
        throw mismatch(s, lightName(scene.lights[i], i) + " is a " + lightName(other.lights[i], i) +
                              " there");
  }

  // Placements: a motion wherever some step differs from the first.
  auto motionOf = [&](auto placementAt) -> std::shared_ptr<const TransformMotion> {
    std::vector<Transform> placements;
    bool moves = false;
    for (size_t s = 0; s < k; ++s) {
      placements.push_back(s == 0 ? placementAt(scene) : placementAt(steps[s]));
      moves = moves || !(placements.back().matrix() == placements.front().matrix());
    }
    if (!moves) return nullptr;
    return std::make_shared<const TransformMotion>(std::move(placements));
  };
  for (size_t i = 0; i < scene.entities.size(); ++i) {
    Entity &e = scene.entities[i];
    e.motion = motionOf([i](const Scene &sc) { return sc.entities[i].worldFromObject; });
    if (const Csg *csg = std::get_if<Csg>(&e.shape); csg && csg->tree) {
      // A CSG's parts move each by its own placement: a copy of its tree
      // whose leaves carry their motion and whose bounds hold the shutter.
      // A part's inherited pattern moves with the node it comes from.
      auto tree = std::make_shared<CsgTree>(*csg->tree);
      bool partsMove = false, patternsMove = false;
      for (size_t part = 0; part < tree->leaves.size(); ++part) {
        CsgTree::Leaf &leaf = tree->leaves[part];
        auto leafOf = [i, part](const Scene &sc) -> const CsgTree::Leaf & {
          return std::get<Csg>(sc.entities[i].shape).tree->leaves[part];
        };
        if (leaf.inheritsTexture) {
          leaf.textureMotion = motionOf([&](const Scene &sc) { return leafOf(sc).textureSpace; });
          patternsMove = patternsMove || leaf.textureMotion;
        }
        leaf.entity.motion =
            motionOf([&](const Scene &sc) { return leafOf(sc).entity.worldFromObject; });
        if (!leaf.entity.motion) continue;
        partsMove = true;
        leaf.bounds = shapeWorldBounds(leaf.entity);
      }
      if (partsMove || patternsMove) {
        tree->finish();
        e.shape = Csg{std::move(tree)};
      }
    }
    if (e.isMesh() && e.mesh && !e.mesh->triangles.empty()) {
      // Vertices that move: the mesh at every step.
      auto motion = std::make_shared<MeshMotion>();
      bool deforms = false;
      for (size_t s = 0; s < k; ++s) {
        const MeshDataPtr &m = s == 0 ? e.mesh : steps[s].entities[i].mesh;
        deforms = deforms || !sameVertices(*e.mesh, *m);
        motion->steps.push_back(m);
      }
      if (deforms) e.vertexMotion = std::move(motion);
    }
  }
  scene.camera.motion = motionOf([](const Scene &sc) { return sc.camera.worldFromCamera; });

  bool lightsMove = false;
  std::vector<std::shared_ptr<const LightMotion>> lightMotion(scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Vec3 start = lightPosition(scene.lights[i]);
    LightMotion m;
    bool moves = false;
    for (size_t s = 0; s < k; ++s) {
      m.offsets.push_back(s == 0 ? Vec3() : lightPosition(steps[s].lights[i]) - start);
      moves = moves || !(m.offsets.back() == Vec3());
    }
    if (moves) lightMotion[i] = std::make_shared<const LightMotion>(std::move(m));
    lightsMove = lightsMove || moves;
  }
  if (lightsMove) scene.lightMotion = std::move(lightMotion);
  scene.motionSteps = static_cast<int>(k);
  return scene;
}

} // namespace lray
