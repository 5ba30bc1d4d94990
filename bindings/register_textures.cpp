// Pipeline: script -> scene description. Texture, Finish, the six pigments
// and the texture maps (lua/README.md, "Textures, finishes and pigments").
#include "bindings/register_classes.h"
#include "bindings/scene_objects.h"
#include "bindings/validators.h"

#include <filesystem>
#include <fstream>

namespace lray::lua {

namespace {

using MK = TextureMap::Kind;

template <class P> void pigmentDefaults(PigmentObj &p) { p.pattern = P{}; }

/// The parameters of a pigment of class P (for partAttr).
template <class P> P &params(PigmentObj &p) { return std::get<P>(p.pattern); }

// ImagePigment2D(file): the path is resolved against the script folder now,
// so a missing image is reported at the line that names it.
int newImagePigment(lua_State *L) {
  const auto &cls = *static_cast<const ClassInfo *>(lua_touserdata(L, lua_upvalueindex(2)));
  // Both strings are kept between calls: pushNew below can raise a memory
  // error, whose longjmp would skip a local string's destructor (a leak).
  thread_local std::string file, path;
  try {
    file = LuaValue<std::string>::check(L, 1);
  } catch (const TypeMismatch &e) {
    throwArgumentError("ImagePigment2D", 1, e);
  }
  if (lua_gettop(L) > 1) throwArgumentCount("ImagePigment2D", 1, lua_gettop(L));
  BindingContext &ctx = BindingContext::of(L);
  path = ctx.resolveReadPath(file, "ImagePigment2D");
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
      .attr("absorption", &Finish::absorption)
      .attr("emission", &Finish::emission, nonNegativeColor)
      .attr("fresnel", &Finish::fresnel)
      .attr("roughness", &Finish::roughness, unitInterval);

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
      .defaults(&pigmentDefaults<ColorPigment>)
      .ctor(+[](PigmentObj &p, std::optional<Color> c) {
        params<ColorPigment>(p).color = c.value_or(Color(1, 1, 1));
      })
      .partAttr<&params<ColorPigment>>("color", &ColorPigment::color);
  reg.cls<PigmentObj>("CheckerPigment2D")
      .defaults(&pigmentDefaults<CheckerPigment2D>)
      .ctor(+[](PigmentObj &) {})
      .attr("pigment1", &PigmentObj::pigment1)
      .attr("pigment2", &PigmentObj::pigment2)
      .attr("texture_map", &PigmentObj::map2);
  reg.cls<PigmentObj>("CheckerPigment3D")
      .defaults(&pigmentDefaults<CheckerPigment3D>)
      .ctor(+[](PigmentObj &) {})
      .attr("pigment1", &PigmentObj::pigment1)
      .attr("pigment2", &PigmentObj::pigment2)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("MarblePigment3D")
      .defaults(&pigmentDefaults<MarblePigment3D>)
      .ctor(+[](PigmentObj &) {})
      .partAttr<&params<MarblePigment3D>>("color1", &MarblePigment3D::color1)
      .partAttr<&params<MarblePigment3D>>("color2", &MarblePigment3D::color2)
      .partAttr<&params<MarblePigment3D>>("frequency", &MarblePigment3D::frequency)
      // `period`: the original example scenes' name for the frequency.
      .partAttr<&params<MarblePigment3D>>("period", &MarblePigment3D::frequency)
      .partAttr<&params<MarblePigment3D>>("power", &MarblePigment3D::power)
      .partAttr<&params<MarblePigment3D>>("size", &MarblePigment3D::size, positiveNumber)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("WoodPigment3D")
      .defaults(&pigmentDefaults<WoodPigment3D>)
      .ctor(+[](PigmentObj &) {})
      .partAttr<&params<WoodPigment3D>>("color1", &WoodPigment3D::color1)
      .partAttr<&params<WoodPigment3D>>("color2", &WoodPigment3D::color2)
      .partAttr<&params<WoodPigment3D>>("frequency", &WoodPigment3D::frequency)
      .partAttr<&params<WoodPigment3D>>("period", &WoodPigment3D::frequency)
      .partAttr<&params<WoodPigment3D>>("power", &WoodPigment3D::power)
      .partAttr<&params<WoodPigment3D>>("size", &WoodPigment3D::size, positiveNumber)
      .attr("texture_map", &PigmentObj::map3);
  reg.cls<PigmentObj>("ImagePigment2D")
      .defaults(&pigmentDefaults<ImagePigment2D>)
      .rawCtor(&newImagePigment)
      .attr("texture_map", &PigmentObj::map2);

  reg.cls<TextureObj>("Texture")
      .ctor(+[](TextureObj &) {})
      .attr("finish", &TextureObj::finish)
      .attr("pigment", &TextureObj::pigment);
}

} // namespace lray::lua
