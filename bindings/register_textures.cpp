// Pipeline: script -> scene description. Texture, Finish, the six pigments
// and the texture maps (SPEC 7).
#include "bindings/register_classes.h"
#include "bindings/scene_objects.h"
#include "bindings/validators.h"

#include <filesystem>
#include <fstream>

namespace lray::lua {

namespace {

using PK = Pigment::Kind;
using MK = TextureMap::Kind;

// ImagePigment2D(file): the path is resolved against the script folder now,
// so a missing image is reported at the line that names it.
int newImagePigment(lua_State *L) {
  const auto &cls = *static_cast<const ClassInfo *>(lua_touserdata(L, lua_upvalueindex(2)));
  std::string file;
  try {
    file = LuaValue<std::string>::check(L, 1);
  } catch (const TypeMismatch &e) {
    throwArgumentError("ImagePigment2D", 1, e);
  }
  if (lua_gettop(L) > 1) throwArgumentCount("ImagePigment2D", 1, lua_gettop(L));
  BindingContext &ctx = BindingContext::of(L);
  std::string path = ctx.resolvePath(file);
  if (!std::filesystem::is_regular_file(path) || !std::ifstream(path, std::ios::binary))
    throw ScriptError("ImagePigment2D: cannot read image '" + file + "' (looked for " + path + ")");
  PigmentObj &p = pushNew<PigmentObj>(L, cls);
  p.imagePath = path;
  p.loc = ctx.currentLocation(L);
  return 1;
}

} // namespace

void registerTextureClasses(Registry &reg) {
  reg.cls<FinishObj>("Finish")
      .ctor(+[](FinishObj &) {})
      .attr("ambient", &Finish::ambient)
      .attr("diffuse", &Finish::diffuse)
      .attr("specular", &Finish::specular)
      .attr("exponent", &Finish::exponent)
      .attr("reflection", &Finish::reflection)
      .attr("refraction", &Finish::refraction)
      .attr("refraction_index", &Finish::refractionIndex)
      .attr("absorption", &Finish::absorption);

  // Texture maps: the first class of each C++ type is its default.
  reg.cls<Map2DObj>("TextureMap2D")
      .defaults(+[](Map2DObj &m) { m.kind = MK::TextureMap2D; })
      .ctor(+[](Map2DObj &) {});
  reg.cls<Map2DObj>("UVMap")
      .defaults(+[](Map2DObj &m) { m.kind = MK::UVMap; })
      .ctor(+[](Map2DObj &) {})
      .attr("scale_s", &TextureMap::scaleS)
      .attr("scale_t", &TextureMap::scaleT)
      .attr("translate_s", &TextureMap::translateS)
      .attr("translate_t", &TextureMap::translateT);
  reg.cls<Map2DObj>("SphericalMap")
      .defaults(+[](Map2DObj &m) { m.kind = MK::SphericalMap; })
      .ctor(+[](Map2DObj &) {});
  reg.cls<Map2DObj>("CylindricalMap")
      .defaults(+[](Map2DObj &m) { m.kind = MK::CylindricalMap; })
      .ctor(+[](Map2DObj &) {});
  reg.cls<Map3DObj>("TextureMap3D")
      .defaults(+[](Map3DObj &m) { m.kind = MK::TextureMap3D; })
      .ctor(+[](Map3DObj &) {});
  reg.cls<Map3DObj>("LinearMap")
      .defaults(+[](Map3DObj &m) { m.kind = MK::LinearMap; })
      .ctor(+[](Map3DObj &) {})
      .attr("transform", &TextureMap::transform);

  // Pigments: ColorPigment first, so an unassigned pigment reads as white.
  reg.cls<PigmentObj>("ColorPigment")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Color; })
      .ctor(+[](PigmentObj &p, std::optional<Color> c) { p.color = c.value_or(Color(1, 1, 1)); })
      .attr("color", &Pigment::color);
  reg.cls<PigmentObj>("CheckerPigment2D")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Checker2D; })
      .ctor(+[](PigmentObj &) {})
      .attr("pigment1", &PigmentObj::pigment1)
      .attr("pigment2", &PigmentObj::pigment2)
      .attr("texture_map", &PigmentObj::map2);
  reg.cls<PigmentObj>("CheckerPigment3D")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Checker3D; })
      .ctor(+[](PigmentObj &) {})
      .attr("pigment1", &PigmentObj::pigment1)
      .attr("pigment2", &PigmentObj::pigment2)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("MarblePigment3D")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Marble3D; p.frequency = {5, 5, 5}; })
      .ctor(+[](PigmentObj &) {})
      .attr("color1", &Pigment::color1)
      .attr("color2", &Pigment::color2)
      .attr("frequency", &Pigment::frequency)
      .attr("period", &Pigment::frequency) // the original example scenes' name
      .attr("power", &Pigment::power)
      .attr("size", &Pigment::size, positiveNumber)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("WoodPigment3D")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Wood3D; p.frequency = {1024, 1024, 1024}; })
      .ctor(+[](PigmentObj &) {})
      .attr("color1", &Pigment::color1)
      .attr("color2", &Pigment::color2)
      .attr("frequency", &Pigment::frequency)
      .attr("period", &Pigment::frequency)
      .attr("power", &Pigment::power)
      .attr("size", &Pigment::size, positiveNumber)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("ImagePigment2D")
      .defaults(+[](PigmentObj &p) { p.kind = PK::Image2D; })
      .rawCtor(&newImagePigment)
      .attr("texture_map", &PigmentObj::map2);

  reg.cls<TextureObj>("Texture")
      .ctor(+[](TextureObj &) {})
      .attr("finish", &TextureObj::finish)
      .attr("pigment", &TextureObj::pigment);
}

} // namespace lray::lua
