// Pipeline: script -> scene description. See scene_converter.h.
#include "bindings/scene_converter.h"

#include "geometry/csg_tree.h"
#include "scene/pigment_uv.h"

#include <memory>

#include <unordered_map>
#include <unordered_set>

namespace lray::lua {

namespace {

/// Limits on CSG trees from scripts: nesting (the converter recurses over
/// it) and the solids in one tree (every one is tested per ray).
constexpr int kMaxCsgNesting = 64;
constexpr size_t kMaxCsgSolids = 4096;
/// And the entries top-level Unions may expand to, in all (one entity each).
constexpr size_t kMaxFlattenedSolids = size_t{1} << 21;

class Converter {
public:
  Converter(const BindingContext &ctx, uint64_t memoryLimit) : ctx_(ctx) {
    out_.memory = MemoryBudget(memoryLimit);
  }

  Scene run(const SceneObj &in) {
    out_.background = in.background;
    if (in.camera) {
      out_.camera = *in.camera;
      out_.camera.loc = ctx_.resolve(in.camera->loc);
    }
    // Charged before the arrays are reserved, each at its own line: one
    // entity added ten million times is refused where it was made.
    for (const LightObj *light : in.lights)
      charge(sizeof(SceneLight), "Light", ctx_.resolve(light->loc));
    out_.lights.reserve(in.lights.size());
    for (const LightObj *light : in.lights) out_.lights.push_back(this->light(*light));
    for (const EntityRef &ref : in.entities) chargeEntity(ref);
    out_.entities.reserve(in.entities.size());
    for (const EntityRef &ref : in.entities) {
      switch (ref.kind) {
      case EntityRefKind::Mesh:
        out_.entities.push_back(mesh(*static_cast<const MeshObj *>(ref.object)));
        break;
      case EntityRefKind::Shape:
        out_.entities.push_back(shape(*static_cast<const EntityObj *>(ref.object)));
        break;
      case EntityRefKind::Csg:
        csg(*static_cast<const CsgObj *>(ref.object), Transform(), Inherited{}, 0);
        break;
      }
    }
    return std::move(out_);
  }

private:
  // ---- the render memory budget (util/memory_budget.h) -------------------------

  void charge(uint64_t bytes, const char *what, const SourceLocation &loc) {
    out_.memory.charge(bytes, what, loc);
  }

  /// An entity's own bytes and its location's file name (a heap string
  /// once past the short-string buffer).
  static uint64_t entityBytes(const SourceLocation &loc) {
    return sizeof(Entity) + (loc.file.size() > 15 ? loc.file.size() + 1 : 0);
  }

  void chargeEntity(const EntityRef &ref) {
    const ScriptLoc *where = nullptr;
    const char *what = "Mesh";
    switch (ref.kind) {
    case EntityRefKind::Mesh: where = &static_cast<const MeshObj *>(ref.object)->loc; break;
    case EntityRefKind::Shape: {
      const auto &e = *static_cast<const EntityObj *>(ref.object);
      where = &e.loc;
      what = shapeName(e.shape);
      break;
    }
    case EntityRefKind::Csg: {
      const auto &c = *static_cast<const CsgObj *>(ref.object);
      where = &c.loc;
      what = csgOpName(c.op);
      break;
    }
    }
    const SourceLocation loc = ctx_.resolve(*where);
    charge(entityBytes(loc), what, loc);
  }

  /// A mesh's triangle data, once per frame however many Meshes share it:
  /// before it is built from the source (an estimate from the face sizes),
  /// or as built when an earlier frame built it.
  void chargeMeshData(const MeshGeometry &g, const SourceLocation &loc) {
    if (!chargedMeshes_.insert(&g).second) return;
    if (g.built) return charge(g.built->memoryBytes(), "Mesh", loc);
    const MeshSource &s = g.source;
    uint64_t triangles = 0;
    for (uint32_t corners : s.faceSizes) triangles += corners >= 2 ? corners - 2 : 0;
    // Positions, given normals plus one computed per vertex, uvs, and each
    // triangle's corners twice (MeshTriangle and the flat index list).
    charge(s.positions.size() * 2 * sizeof(Vec3f) + s.normals.size() * sizeof(Vec3f) +
               s.uvs.size() * sizeof(Vec2f) +
               triangles * (sizeof(MeshTriangle) + 3 * sizeof(uint32_t)),
           "Mesh", loc);
  }

  Transform transform(const Affine &a, const SourceLocation &loc, const char *what) {
    Transform t = a.toTransform();
    if (t.singular()) throw SceneError(loc, std::string(what) + ": the transform is singular");
    return t;
  }

  SceneLight light(const LightObj &obj) {
    SceneLight out = obj.light;
    std::visit(
        [&](auto &l) {
          l.loc = ctx_.resolve(obj.loc);
          if (std::string why = l.invalid(); !why.empty()) throw SceneError(l.loc, why);
        },
        out);
    return out;
  }

  Entity shape(const EntityObj &e) {
    Entity out;
    out.loc = ctx_.resolve(e.loc);
    out.shape = e.shape;
    out.worldFromObject = transform(e.transform, out.loc, shapeName(e.shape));
    setTexture(out, texture(e.texture));
    checkEmitter(out);
    return out;
  }

  /// Gives `e` texture `t`, and says whether that texture may read the
  /// surface's (u, v): a plain colour or a 3-D map reads nothing of them.
  void setTexture(Entity &e, uint32_t t) const {
    e.texture = t;
    e.readsUv = pigmentReadsUv(out_.pigments, out_.textures[t].pigment);
  }

  /// Emission needs a finite area to come from (lua/README.md, Finish).
  void checkEmitter(const Entity &e) const {
    const bool emits = !out_.textures[e.texture].finish.emission.isBlack();
    if (emits && std::holds_alternative<Plane>(e.shape))
      throw SceneError(e.loc, "Plane: its finish emits (emission), but a plane has no finite area "
                              "to emit from");
  }

  // ---- CSG ---------------------------------------------------------------------
  // A top-level Union is its children as entities of their own: it keeps
  // every child's surface, so it is a group, and the backends' trees do
  // better with its parts than a CSG test of all of them per ray. Every
  // other operator becomes one CSG entity holding its whole tree.

  /// The texture children without their own take, and the space of the node
  /// it was set on (its pigment is evaluated there: POV-Ray's rule).
  struct Inherited {
    const TextureObj *texture = nullptr;
    Transform space;
    bool set = false;
  };

  Inherited inherit(const CsgObj &c, const Transform &world, const Inherited &above) {
    if (!c.texture) return above;
    return {c.texture, world, true};
  }

  /// World placement of a child placed by `a` under a node placed at `world`.
  Transform place(const Transform &world, const Affine &a, const SourceLocation &loc,
                  const char *what) {
    Transform t = world * transform(a, loc, what);
    if (t.singular()) throw SceneError(loc, std::string(what) + ": the transform is singular");
    return t;
  }

  Entity csgLeaf(const EntityObj &e, const Transform &parentWorld, const Inherited &inherited,
                 bool &inheritsTexture) {
    Entity out = shape(e);
    if (const char *attribute = hollowedBy(out.shape))
      throw SceneError(out.loc, std::string(shapeName(out.shape)) + " in a CSG: an " +
                                    attribute + " one " + noInside(attribute));
    out.worldFromObject = place(parentWorld, e.transform, out.loc, shapeName(out.shape));
    inheritsTexture = !e.texture && inherited.set;
    if (inheritsTexture) setTexture(out, texture(inherited.texture));
    checkEmitter(out);
    return out;
  }

  void csg(const CsgObj &c, const Transform &parentWorld, const Inherited &above, int depth) {
    const SourceLocation loc = ctx_.resolve(c.loc);
    const char *name = csgOpName(c.op);
    checkCsgDepth(loc, name, depth);
    const Transform world = place(parentWorld, c.transform, loc, name);
    const Inherited inherited = inherit(c, world, above);
    if (c.op != CsgOp::Union) {
      out_.entities.push_back(csgEntity(c, world, inherited, depth));
      return;
    }
    for (const EntityRef &child : c.children) {
      chargeEntity(child); // an entity of its own
      // A Union used twice in one is copied twice: 40 levels of
      // u = Union { u, u } would ask for 2^40 entities.
      if (++flattened_ > kMaxFlattenedSolids)
        throw SceneError(loc, std::string(name) + ": expands to more than " +
                                  std::to_string(kMaxFlattenedSolids) +
                                  " solids (a node listed twice is copied each time)");
      if (child.kind == EntityRefKind::Csg) {
        csg(*static_cast<const CsgObj *>(child.object), world, inherited, depth + 1);
        continue;
      }
      bool inherits = false;
      Entity leaf =
          csgLeaf(*static_cast<const EntityObj *>(child.object), world, inherited, inherits);
      if (!inherits) {
        out_.entities.push_back(std::move(leaf));
        continue;
      }
      // Its pigment lives in the Union's space: a CSG entity of one leaf.
      auto tree = std::make_shared<CsgTree>();
      tree->addNode(CsgOp::Union, CsgTree::kNoParent);
      addLeaf(*tree, std::move(leaf), 0, inherited);
      tree->finish();
      out_.entities.push_back(csgEntityOf(std::move(tree), world, loc));
    }
  }

  void addLeaf(CsgTree &tree, Entity leaf, uint32_t parent, const Inherited &inherited) {
    const uint32_t i = tree.addLeaf(std::move(leaf), parent);
    tree.leaves[i].inheritsTexture = true;
    tree.leaves[i].textureSpace = inherited.space;
  }

  Entity csgEntityOf(std::shared_ptr<CsgTree> tree, const Transform &world,
                     const SourceLocation &loc) {
    Entity out;
    out.loc = loc;
    out.worldFromObject = world;
    setTexture(out, tree->leaves.front().entity.texture);
    out.shape = Csg{std::move(tree)};
    return out;
  }

  Entity csgEntity(const CsgObj &root, const Transform &world, const Inherited &inherited,
                   int depth) {
    auto tree = std::make_shared<CsgTree>();
    const SourceLocation loc = ctx_.resolve(root.loc);
    csgNode(*tree, root, CsgTree::kNoParent, world, inherited, depth);
    if (tree->leaves.size() > kMaxCsgSolids)
      throw SceneError(loc, std::string(csgOpName(root.op)) + ": " +
                                std::to_string(tree->leaves.size()) +
                                " solids in one tree, more than " + std::to_string(kMaxCsgSolids) +
                                " (each ray meeting its bounds tests every one; a Union of "
                                "groups is free: only Merge, Intersection and Difference are "
                                "one tree)");
    tree->finish();
    return csgEntityOf(std::move(tree), world, loc);
  }

  /// Node `c` placed at `world` (its own transform applied) under `parent`.
  void csgNode(CsgTree &tree, const CsgObj &c, uint32_t parent, const Transform &world,
               const Inherited &inherited, int depth) {
    charge(sizeof(CsgTree::Node), csgOpName(c.op), ctx_.resolve(c.loc));
    const uint32_t node = tree.addNode(c.op, parent);
    for (const EntityRef &child : c.children) {
      if (tree.leaves.size() > kMaxCsgSolids) return; // csgEntity reports it
      if (child.kind == EntityRefKind::Csg) {
        const CsgObj &sub = *static_cast<const CsgObj *>(child.object);
        const SourceLocation loc = ctx_.resolve(sub.loc);
        const char *name = csgOpName(sub.op);
        checkCsgDepth(loc, name, depth + 1);
        const Transform subWorld = place(world, sub.transform, loc, name);
        csgNode(tree, sub, node, subWorld, inherit(sub, subWorld, inherited), depth + 1);
        continue;
      }
      bool inherits = false;
      Entity leaf =
          csgLeaf(*static_cast<const EntityObj *>(child.object), world, inherited, inherits);
      // A subtree listed many times is copied each time: charged each time.
      charge(sizeof(CsgTree::Leaf) + entityBytes(leaf.loc), shapeName(leaf.shape), leaf.loc);
      if (inherits) addLeaf(tree, std::move(leaf), node, inherited);
      else tree.addLeaf(std::move(leaf), node);
    }
  }

  static void checkCsgDepth(const SourceLocation &loc, const char *name, int depth) {
    if (depth > kMaxCsgNesting)
      throw SceneError(loc, std::string(name) + ": CSG nodes are nested more than " +
                                std::to_string(kMaxCsgNesting) + " deep");
  }

  Entity mesh(const MeshObj &m) {
    Entity out;
    out.loc = ctx_.resolve(m.loc);
    out.shape = Mesh{};
    out.worldFromObject = transform(m.transform, out.loc, "Mesh");
    out.smooth = m.smooth;
    setTexture(out, texture(m.texture));
    const MeshGeometry &g = *m.geometry;
    chargeMeshData(g, out.loc);
    if (!g.built) {
      try {
        g.built = buildMeshData(g.source);
      } catch (const SceneError &err) {
        throw SceneError(out.loc, std::string("Mesh: ") + err.what());
      }
    }
    if (g.built->triangles.empty())
      throw SceneError(out.loc, "Mesh: has no faces (set its vertices and indices)");
    out.mesh = g.built;
    return out;
  }

  uint32_t texture(const TextureObj *t) {
    // Consecutive entities usually share a texture: skip the hash lookup.
    if (lastTextureValid_ && t == lastTexture_) return lastTextureIndex_;
    lastTexture_ = t;
    lastTextureValid_ = true;
    lastTextureIndex_ = textureLookup(t);
    return lastTextureIndex_;
  }

  uint32_t textureLookup(const TextureObj *t) {
    auto it = textures_.find(t);
    if (it != textures_.end()) return it->second;
    Texture out;
    if (t) out.loc = ctx_.resolve(t->loc);
    if (t && t->finish) out.finish = *t->finish;
    out.pigment = pigment(t ? t->pigment : nullptr);
    auto index = static_cast<uint32_t>(out_.textures.size());
    out_.textures.push_back(out);
    textures_.emplace(t, index); // null (the default texture) is cached too
    return index;
  }

  uint32_t pigment(const PigmentObj *p, int depth = 0) {
    auto it = pigments_.find(p);
    if (it != pigments_.end()) return it->second;
    Pigment out;
    if (p) {
      out.loc = ctx_.resolve(p->loc);
      if (!inProgress_.insert(p).second)
        throw SceneError(out.loc, std::string(pigmentName(p->pattern)) +
                                      ": the pigment contains itself");
      if (depth > kMaxPigmentNesting)
        throw SceneError(out.loc, std::string(pigmentName(p->pattern)) +
                                      ": pigments are nested more than " +
                                      std::to_string(kMaxPigmentNesting) + " deep");
      out.pattern = p->pattern;
      std::visit(
          [&](auto &pattern) {
            if constexpr (requires { pattern.pigment1; }) {
              // Children first: they get smaller indices (bottom-up table).
              pattern.pigment1 = pigment(p->pigment1, depth + 1);
              pattern.pigment2 = pigment(p->pigment2, depth + 1);
            }
            if constexpr (requires { pattern.image; }) pattern.image = image(p->imagePath, p->loc);
          },
          out.pattern);
      // Each pigment states its dimensions; the map defaults to match.
      switch (pigmentDimensions(out.pattern)) {
      case 3:
        out.map = p->map3 ? static_cast<const TextureMap &>(*p->map3) : TextureMap{};
        if (p->map3) out.map.loc = ctx_.resolve(p->map3->loc);
        else out.map.kind = TextureMap::Kind::TextureMap3D;
        break;
      case 2:
        out.map = p->map2 ? static_cast<const TextureMap &>(*p->map2) : TextureMap{};
        if (p->map2) out.map.loc = ctx_.resolve(p->map2->loc);
        break;
      default: break;
      }
      inProgress_.erase(p);
    }
    auto index = static_cast<uint32_t>(out_.pigments.size());
    out_.pigments.push_back(std::move(out));
    pigments_.emplace(p, index);
    return index;
  }

  uint32_t image(const std::string &path, ScriptLoc loc) {
    auto it = images_.find(path);
    if (it != images_.end()) return it->second;
    auto index = static_cast<uint32_t>(out_.images.size());
    out_.images.push_back({path, ctx_.resolve(loc)});
    images_.emplace(path, index);
    return index;
  }

  const BindingContext &ctx_;
  Scene out_;
  size_t flattened_ = 0; ///< entries of top-level Unions expanded so far
  const TextureObj *lastTexture_ = nullptr;
  bool lastTextureValid_ = false;
  uint32_t lastTextureIndex_ = 0;
  std::unordered_map<const TextureObj *, uint32_t> textures_;
  std::unordered_map<const PigmentObj *, uint32_t> pigments_;
  std::unordered_map<std::string, uint32_t> images_;
  std::unordered_set<const PigmentObj *> inProgress_;
  std::unordered_set<const MeshGeometry *> chargedMeshes_;
};

} // namespace

Scene convertScene(const SceneObj &scene, const BindingContext &ctx, uint64_t memoryLimit) {
  return Converter(ctx, memoryLimit).run(scene);
}

} // namespace lray::lua
