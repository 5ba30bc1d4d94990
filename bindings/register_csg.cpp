// Pipeline: script -> scene description. The CSG operators (lua/README.md,
// "CSG"): Union, Merge, Intersection and Difference, each constructed from a
// table that lists its solids, with attributes by name:
//   Difference { Cube(), Sphere(Scale(0.6)), texture = t, transform = Rotate(y, 30) }
#include "bindings/class_names.h"
#include "bindings/register_classes.h"
#include "bindings/scene_objects.h"

#include <string>

namespace lray::lua {

namespace {

/// "a solid (Sphere, ... or Difference)": the shapes of a solid kind.
const std::string &solidsExpected() {
  static const std::string text = "a solid (" + classNames<Shape, SolidKind>() + ")";
  return text;
}

/// The child at stack index i, entry `entry` of the constructor's table.
EntityRef solidRef(lua_State *L, int i, const std::string &op, lua_Integer entry) {
  const std::string where = op + ": entry " + std::to_string(entry);
  if (const EntityObj *e = toObject<EntityObj>(L, i)) {
    if (const char *attribute = hollowedBy(e->shape))
      throw ScriptError(where + " is an " + attribute + " " + shapeName(e->shape) + ", which " +
                        noInside(attribute));
    return {e, EntityRefKind::Shape};
  }
  if (const CsgObj *c = toObject<CsgObj>(L, i)) return {c, EntityRefKind::Csg};
  if (toObject<MeshObj>(L, i))
    throw ScriptError(where + " is a Mesh, which CSG does not take: it expects " +
                      solidsExpected());
  throw ScriptError(where + " expects " + solidsExpected() + ", got " + typeName(L, i));
}

template <CsgOp Op> int csgNew(lua_State *L) {
  const auto &cls = *static_cast<const ClassInfo *>(lua_touserdata(L, lua_upvalueindex(2)));
  const std::string op = csgOpName(Op);
  if (lua_gettop(L) != 1 || lua_type(L, 1) != LUA_TTABLE)
    throw ScriptError(op + ": expects one table listing its solids, as in " + op +
                      " { a, b, texture = t }, got " +
                      (lua_gettop(L) == 0 ? std::string("nothing")
                                          : lua_gettop(L) > 1 ? std::to_string(lua_gettop(L)) +
                                                                    " arguments"
                                                              : typeName(L, 1)));
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, 1));
  if (n == 0)
    throw ScriptError(op + ": the list of solids is empty (it needs at least one, as in " + op +
                      " { a, b })");
  CsgObj &obj = pushNew<CsgObj>(L, cls);
  const int self = lua_gettop(L);
  obj.op = Op;
  obj.loc = BindingContext::of(L).currentLocation(L);
  lua_createtable(L, static_cast<int>(std::min<lua_Integer>(n, 1 << 20)), 0);
  const int kids = lua_gettop(L);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, 1, i);
    obj.children.push_back(solidRef(L, -1, op, i));
    lua_rawseti(L, kids, i);
  }
  lua_setiuservalue(L, self, CsgObj::kChildrenSlot);
  // Attributes by name; any other key is a mistake (a hole in the list).
  lua_pushnil(L);
  while (lua_next(L, 1) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) {
      assignAttribute(L, cls, self, -2, -1);
    } else if (!lua_isinteger(L, -2) || lua_tointeger(L, -2) < 1 || lua_tointeger(L, -2) > n) {
      throw ScriptError(op + ": its table holds solids listed from 1 on and attributes by name; " +
                        "key " + describeValue(L, -2) +
                        " is neither (a nil in the list of solids?)");
    }
    lua_pop(L, 1);
  }
  lua_settop(L, self);
  return 1;
}

/// u.children: a new list of the node's solids (changing it changes nothing).
void getChildren(lua_State *L, CsgObj &c, int self) {
  lua_getiuservalue(L, self, CsgObj::kChildrenSlot);
  const int kids = lua_gettop(L);
  const auto n = static_cast<lua_Integer>(c.children.size());
  lua_createtable(L, static_cast<int>(n), 0);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, kids, i);
    lua_rawseti(L, -2, i);
  }
  lua_remove(L, kids);
}

template <CsgOp Op> void registerOp(Registry &reg) {
  auto b = reg.cls<CsgObj>(csgOpName(Op));
  entityAttributes(b);
  if (b.userValueSlot() != CsgObj::kChildrenSlot)
    throw std::logic_error("CsgObj::kChildrenSlot is not the children's user value");
  b.property("children", &getChildren, nullptr).rawCtor(&csgNew<Op>);
}

} // namespace

void registerCsgClasses(Registry &reg) {
  registerOp<CsgOp::Union>(reg);
  registerOp<CsgOp::Merge>(reg);
  registerOp<CsgOp::Intersection>(reg);
  registerOp<CsgOp::Difference>(reg);
}

} // namespace lray::lua
