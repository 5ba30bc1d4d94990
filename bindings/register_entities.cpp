// Pipeline: script -> scene description. The shapes (lua/README.md, "Entities"), Mesh with its
// Lua-table arrays, and the native mesh_from_obj.
#include "bindings/lua_allocator.h"
#include "bindings/register_classes.h"
#include "bindings/scene_objects.h"
#include "bindings/validators.h"
#include "scene/obj_loader.h"

#include <cmath>
#include <limits>

namespace lray::lua {

namespace {

// ---- Mesh arrays: Lua tables <-> MeshSource ---------------------------------------

[[noreturn]] void badEntry(const char *attribute, const char *shape, lua_Integer entry,
                           const std::string &given) {
  throw ScriptError(std::string("Mesh: attribute '") + attribute + "' expects a list of " + shape +
                    ", entry " + std::to_string(entry) + " is " + given);
}

void checkList(lua_State *L, int value, const char *attribute, const char *shape) {
  if (lua_type(L, value) != LUA_TTABLE)
    throw ScriptError(std::string("Mesh: attribute '") + attribute + "' expects a list of " +
                      shape + ", got " + typeName(L, value));
}

// Reads list entry i (a table of n finite numbers) into out.
void readNumbers(lua_State *L, int value, lua_Integer i, int n, const char *attribute,
                 const char *shape, double *out) {
  if (lua_rawgeti(L, value, i) != LUA_TTABLE) badEntry(attribute, shape, i, typeName(L, -1));
  int entry = lua_gettop(L);
  if (static_cast<int>(lua_rawlen(L, entry)) != n)
    badEntry(attribute, shape, i,
             "a table of " + std::to_string(lua_rawlen(L, entry)) + " values");
  for (int k = 0; k < n; ++k) {
    if (lua_rawgeti(L, entry, k + 1) != LUA_TNUMBER)
      badEntry(attribute, shape, i, "a table holding " + typeName(L, -1));
    out[k] = lua_tonumber(L, -1);
    if (!std::isfinite(out[k]))
      badEntry(attribute, shape, i,
               "a table holding the non-finite number " + describeValue(L, -1));
    // Mesh data is stored in single precision (shared with Embree).
    if (std::fabs(out[k]) > std::numeric_limits<float>::max())
      badEntry(attribute, shape, i,
               "a table holding " + describeValue(L, -1) + ", out of range for single precision");
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

std::vector<Vec3f> readVec3List(lua_State *L, int value, const char *attribute) {
  checkList(L, value, attribute, "{x, y, z}");
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, value));
  std::vector<Vec3f> out;
  out.reserve(static_cast<size_t>(n));
  for (lua_Integer i = 1; i <= n; ++i) {
    double v[3];
    readNumbers(L, value, i, 3, attribute, "{x, y, z}", v);
    out.push_back({float(v[0]), float(v[1]), float(v[2])});
  }
  return out;
}

/// Inside a loop that builds a Lua table per element: the tables take ten
/// times the charged arrays they come from, and the deferred limit would
/// only see them when the call returns, so the limit is checked as they grow.
void checkMemoryEvery(lua_State *L, size_t i, const char *what) {
  if (i % 4096 == 4095) BindingContext::of(L).checkMemory(L, what);
}

void pushVec3List(lua_State *L, const std::vector<Vec3f> &list, const char *what) {
  lua_createtable(L, static_cast<int>(list.size()), 0);
  for (size_t i = 0; i < list.size(); ++i) {
    checkMemoryEvery(L, i, what);
    lua_createtable(L, 3, 0);
    const float c[3] = {list[i].x, list[i].y, list[i].z};
    for (int k = 0; k < 3; ++k) {
      lua_pushnumber(L, c[k]);
      lua_rawseti(L, -2, k + 1);
    }
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}

// A 1-based index from Lua into 0-based; `what` names it in messages.
int32_t readIndex(lua_State *L, int i, lua_Integer face, int corner, const char *what) {
  double v = lua_tonumber(L, i);
  if (lua_type(L, i) != LUA_TNUMBER || v != std::floor(v) || v < 1 || v > 2147483647.0)
    throw ScriptError("Mesh: attribute 'indices': face " + std::to_string(face) + ", corner " +
                      std::to_string(corner) + ": " + what +
                      " index must be a positive integer, got " + describeValue(L, i));
  return static_cast<int32_t>(v) - 1;
}

void readIndices(lua_State *L, int value, MeshSource &src) {
  if (lua_type(L, value) != LUA_TTABLE)
    throw ScriptError("Mesh: attribute 'indices' expects a list of faces, got " +
                      typeName(L, value));
  std::vector<MeshCorner> corners;
  std::vector<uint32_t> sizes;
  lua_Integer faces = static_cast<lua_Integer>(lua_rawlen(L, value));
  for (lua_Integer f = 1; f <= faces; ++f) {
    if (lua_rawgeti(L, value, f) != LUA_TTABLE)
      throw ScriptError("Mesh: attribute 'indices': face " + std::to_string(f) +
                        " must be a list of corners, got " + typeName(L, -1));
    int face = lua_gettop(L);
    int n = static_cast<int>(lua_rawlen(L, face));
    if (n < 3)
      throw ScriptError("Mesh: attribute 'indices': face " + std::to_string(f) + " has " +
                        std::to_string(n) + " corners, needs at least 3");
    for (int c = 1; c <= n; ++c) {
      MeshCorner corner;
      int type = lua_rawgeti(L, face, c);
      if (type == LUA_TNUMBER) {
        corner.v = readIndex(L, -1, f, c, "vertex");
      } else if (type == LUA_TTABLE) {
        int t = lua_gettop(L);
        lua_rawgeti(L, t, 1);
        corner.v = readIndex(L, -1, f, c, "vertex");
        if (lua_rawgeti(L, t, 2) != LUA_TNIL) corner.uv = readIndex(L, -1, f, c, "uv");
        if (lua_rawgeti(L, t, 3) != LUA_TNIL) corner.n = readIndex(L, -1, f, c, "normal");
        if (lua_rawgeti(L, t, 4) != LUA_TNIL)
          throw ScriptError("Mesh: attribute 'indices': face " + std::to_string(f) + ", corner " +
                            std::to_string(c) + " has more than 3 entries {v, uv, n}");
        lua_settop(L, t);
      } else {
        throw ScriptError("Mesh: attribute 'indices': face " + std::to_string(f) + ", corner " +
                          std::to_string(c) + " must be an index or {v, uv, n}, got " +
                          typeName(L, -1));
      }
      lua_settop(L, face);
      corners.push_back(corner);
    }
    sizes.push_back(static_cast<uint32_t>(n));
    lua_settop(L, face - 1);
  }
  src.corners = std::move(corners);
  src.faceSizes = std::move(sizes);
}

void pushIndex(lua_State *L, int32_t index) {
  if (index < 0)
    lua_pushnil(L);
  else
    lua_pushinteger(L, index + 1);
}

void pushIndices(lua_State *L, const MeshSource &src) {
  lua_createtable(L, static_cast<int>(src.faceSizes.size()), 0);
  size_t first = 0;
  for (size_t f = 0; f < src.faceSizes.size(); ++f) {
    checkMemoryEvery(L, f, "Mesh: indices");
    lua_createtable(L, static_cast<int>(src.faceSizes[f]), 0);
    for (uint32_t c = 0; c < src.faceSizes[f]; ++c) {
      const MeshCorner &k = src.corners[first + c];
      if (k.uv < 0 && k.n < 0) {
        pushIndex(L, k.v);
      } else {
        lua_createtable(L, 3, 0);
        const int32_t parts[3] = {k.v, k.uv, k.n};
        for (int i = 0; i < 3; ++i) {
          pushIndex(L, parts[i]);
          lua_rawseti(L, -2, i + 1);
        }
      }
      lua_rawseti(L, -2, c + 1);
    }
    lua_rawseti(L, -2, static_cast<lua_Integer>(f + 1));
    first += src.faceSizes[f];
  }
}

int meshCopy(lua_State *L) {
  const MeshObj &self = checkSelf<MeshObj>(L, "Mesh:copy");
  const ClassInfo &cls = *objHeader(L, 1)->cls;
  MeshObj &copy = pushNew<MeshObj>(L, cls);
  copy.geometry = self.geometry; // shared: copies never duplicate the arrays
  copy.transform = self.transform;
  copy.smooth = self.smooth;
  copy.loc = BindingContext::of(L).currentLocation(L);
  if (self.texture) {
    copy.texture = self.texture;
    lua_getiuservalue(L, 1, 1);
    lua_setiuservalue(L, -2, 1);
  }
  return 1;
}

// mesh_from_obj(path): parsed natively; the path is relative to the script.
/// Charges the mesh's arrays to the script's memory and checks the limit.
void chargeMesh(lua_State *L, MeshObj &m, const char *what) {
  const MeshSource &s = m.geometry->source;
  const size_t bytes = s.positions.capacity() * sizeof(Vec3f) +
                       s.normals.capacity() * sizeof(Vec3f) + s.uvs.capacity() * sizeof(Vec2f) +
                       s.corners.capacity() * sizeof(MeshCorner) +
                       s.faceSizes.capacity() * sizeof(uint32_t);
  BindingContext &ctx = BindingContext::of(L);
  // The place a memory error soon after is blamed on (Lua gives it none).
  ctx.lastSeen = ctx.currentLocation(L);
  if (ctx.allocator) m.geometry->charge.set(ctx.allocator->external(), bytes);
  ctx.checkMemory(L, what);
}

int meshFromObj(lua_State *L) {
  std::string file;
  try {
    file = LuaValue<std::string>::check(L, 1);
  } catch (const TypeMismatch &e) {
    throwArgumentError("mesh_from_obj", 1, e);
  }
  BindingContext &ctx = BindingContext::of(L);
  MeshSource source;
  // What the script has left of --script-memory bounds the parse as it goes.
  uint64_t left = 0;
  if (ctx.allocator && ctx.allocator->limit()) {
    const uint64_t used = ctx.allocator->bytesInUse() + ctx.allocator->external()->bytes.load();
    left = used < ctx.allocator->limit() ? ctx.allocator->limit() - used : 1;
  }
  try {
    source = loadObj(ctx.resolveReadPath(file, "mesh_from_obj"), file, ctx.maxFileBytes, left);
  } catch (const SceneError &e) {
    throw ScriptError(std::string("mesh_from_obj: ") + e.what());
  }
  MeshObj &mesh = pushNew<MeshObj>(L, ctx.primary(typeTag<MeshObj>()));
  mesh.geometry->source = std::move(source);
  mesh.loc = ctx.currentLocation(L);
  chargeMesh(L, mesh, "mesh_from_obj");
  return 1;
}

void getVertices(lua_State *L, MeshObj &m, int) {
  pushVec3List(L, m.geometry->source.positions, "Mesh: vertices");
}
void setVertices(lua_State *L, MeshObj &m, int, int v) {
  m.editSource().positions = readVec3List(L, v, "vertices");
  chargeMesh(L, m, "Mesh: vertices");
}
void getNormals(lua_State *L, MeshObj &m, int) {
  pushVec3List(L, m.geometry->source.normals, "Mesh: normals");
}
void setNormals(lua_State *L, MeshObj &m, int, int v) {
  m.editSource().normals = readVec3List(L, v, "normals");
  chargeMesh(L, m, "Mesh: normals");
}

void getUvs(lua_State *L, MeshObj &m, int) {
  const auto &uvs = m.geometry->source.uvs;
  lua_createtable(L, static_cast<int>(uvs.size()), 0);
  for (size_t i = 0; i < uvs.size(); ++i) {
    checkMemoryEvery(L, i, "Mesh: uvs");
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, uvs[i].u);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, uvs[i].v);
    lua_rawseti(L, -2, 2);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}
void setUvs(lua_State *L, MeshObj &m, int, int v) {
  checkList(L, v, "uvs", "{u, v}");
  std::vector<Vec2f> uvs;
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, v));
  for (lua_Integer i = 1; i <= n; ++i) {
    double uv[2];
    readNumbers(L, v, i, 2, "uvs", "{u, v}", uv);
    uvs.push_back({float(uv[0]), float(uv[1])});
  }
  m.editSource().uvs = std::move(uvs);
  chargeMesh(L, m, "Mesh: uvs");
}

void getIndices(lua_State *L, MeshObj &m, int) { pushIndices(L, m.geometry->source); }
void setIndices(lua_State *L, MeshObj &m, int, int v) {
  MeshSource parsed; // parse fully before touching the mesh
  readIndices(L, v, parsed);
  MeshSource &src = m.editSource();
  src.corners = std::move(parsed.corners);
  src.faceSizes = std::move(parsed.faceSizes);
  chargeMesh(L, m, "Mesh: indices");
}

template <class S> void shapeDefaults(EntityObj &e) { e.shape = S{}; }

/// The shape parameters of an entity of class S (for partAttr).
template <class S> S &params(EntityObj &e) { return std::get<S>(e.shape); }

void shapeCtor(EntityObj &e, std::optional<Affine> t) {
  if (t) e.transform = *t;
}

/// Shape class S (its name, defaults and constructor) with the attributes
/// every entity has.
template <class S> ClassBuilder<EntityObj> shapeClass(Registry &reg) {
  return entityAttributes(
      reg.cls<EntityObj>(S::kName).defaults(&shapeDefaults<S>).ctor(&shapeCtor));
}

} // namespace

void registerEntityClasses(Registry &reg) {
  shapeClass<Sphere>(reg);
  shapeClass<Cube>(reg);
  shapeClass<Cylinder>(reg).partAttr<&params<Cylinder>>("open", &Cylinder::open);
  shapeClass<Cone>(reg).partAttr<&params<Cone>>("open", &Cone::open);
  shapeClass<Plane>(reg);
  shapeClass<Torus>(reg)
      .partAttr<&params<Torus>>("major", &Torus::major, positiveNumber)
      .partAttr<&params<Torus>>("minor", &Torus::minor, positiveNumber);

  entityAttributes(reg.cls<MeshObj>("Mesh")
                       .ctor(+[](MeshObj &m, std::optional<Affine> t) {
                         if (t) m.transform = *t;
                       }))
      .attr("smooth", &MeshObj::smooth)
      .property("vertices", &getVertices, &setVertices)
      .property("normals", &getNormals, &setNormals)
      .property("uvs", &getUvs, &setUvs)
      .property("indices", &getIndices, &setIndices)
      .rawMethod("copy", &meshCopy);

  reg.rawFunction("mesh_from_obj", &meshFromObj);
}

} // namespace lray::lua
