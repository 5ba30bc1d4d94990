// Pipeline: script -> scene description. See scene_converter.h.
#include "bindings/scene_converter.h"

#include <unordered_map>
#include <unordered_set>

namespace lray::lua {

namespace {

class Converter {
public:
  explicit Converter(const BindingContext &ctx) : ctx_(ctx) {}

  Scene run(const SceneObj &in) {
    out_.background = in.background;
    if (in.camera) {
      out_.camera = *in.camera;
      out_.camera.loc = ctx_.resolve(in.camera->loc);
    }
    out_.lights.reserve(in.lights.size());
    for (const LightObj *light : in.lights) out_.lights.push_back(this->light(*light));
    out_.entities.reserve(in.entities.size());
    for (const EntityRef &ref : in.entities) {
      if (ref.isMesh)
        out_.entities.push_back(mesh(*static_cast<const MeshObj *>(ref.object)));
      else
        out_.entities.push_back(shape(*static_cast<const EntityObj *>(ref.object)));
    }
    return std::move(out_);
  }

private:
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
    out.texture = texture(e.texture);
    return out;
  }

  Entity mesh(const MeshObj &m) {
    Entity out;
    out.loc = ctx_.resolve(m.loc);
    out.shape = Mesh{};
    out.worldFromObject = transform(m.transform, out.loc, "Mesh");
    out.smooth = m.smooth;
    out.texture = texture(m.texture);
    const MeshGeometry &g = *m.geometry;
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
  const TextureObj *lastTexture_ = nullptr;
  bool lastTextureValid_ = false;
  uint32_t lastTextureIndex_ = 0;
  std::unordered_map<const TextureObj *, uint32_t> textures_;
  std::unordered_map<const PigmentObj *, uint32_t> pigments_;
  std::unordered_map<std::string, uint32_t> images_;
  std::unordered_set<const PigmentObj *> inProgress_;
};

} // namespace

Scene convertScene(const SceneObj &scene, const BindingContext &ctx) {
  return Converter(ctx).run(scene);
}

} // namespace lray::lua
