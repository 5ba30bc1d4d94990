// Pipeline: script -> scene description. Vector, Color and Transform (lua/README.md, "Values"):
// value types whose arithmetic runs in C++.
#include "bindings/register_classes.h"
#include "util/printable_text.h"

#include <cmath>

namespace lray::lua {

namespace {

// Factories and products are checked where they are made, so a singular
// matrix is reported at the script line that creates it.
Affine checked(const Affine &a, const std::string &what) {
  if (a.singular()) throw ScriptError(what);
  return a;
}

Affine checked(const Transform &t, const char *what) {
  if (t.singular()) throw ScriptError(std::string(what));
  return Affine::from(t);
}

int vectorMul(lua_State *L) {
  const Vec3 *a = toObject<Vec3>(L, 1), *b = toObject<Vec3>(L, 2);
  if (a && lua_type(L, 2) == LUA_TNUMBER) {
    LuaValue<Vec3>::push(L, *a * LuaValue<double>::check(L, 2));
  } else if (b && lua_type(L, 1) == LUA_TNUMBER) {
    LuaValue<Vec3>::push(L, LuaValue<double>::check(L, 1) * *b);
  } else {
    throw ScriptError("Vector: '*' multiplies a Vector by a number, got " + typeName(L, 1) +
                      " * " + typeName(L, 2) + " (use v:dot(w) or v:cross(w))");
  }
  return 1;
}

int colorMul(lua_State *L) {
  const Color *a = toObject<Color>(L, 1), *b = toObject<Color>(L, 2);
  if (a && b) {
    LuaValue<Color>::push(L, *a * *b);
  } else if (a && lua_type(L, 2) == LUA_TNUMBER) {
    LuaValue<Color>::push(L, *a * LuaValue<double>::check(L, 2));
  } else if (b && lua_type(L, 1) == LUA_TNUMBER) {
    LuaValue<Color>::push(L, LuaValue<double>::check(L, 1) * *b);
  } else {
    throw ScriptError("Color: '*' multiplies a Color by a number or a Color, got " +
                      typeName(L, 1) + " * " + typeName(L, 2));
  }
  return 1;
}

template <class T> int valueEq(lua_State *L) {
  const T *a = toObject<T>(L, 1), *b = toObject<T>(L, 2);
  lua_pushboolean(L, a && b && *a == *b);
  return 1;
}

int vectorToString(lua_State *L) {
  const Vec3 &v = checkObjectValue<Vec3>(L, 1);
  std::string s = "Vector(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ", " +
                  formatNumber(v.z) + ")";
  lua_pushlstring(L, s.data(), s.size());
  return 1;
}

int colorToString(lua_State *L) {
  const Color &c = checkObjectValue<Color>(L, 1);
  std::string s = "Color(" + formatNumber(c.r) + ", " + formatNumber(c.g) + ", " +
                  formatNumber(c.b) + ")";
  lua_pushlstring(L, s.data(), s.size());
  return 1;
}

int transformToString(lua_State *L) {
  const Affine &a = checkObjectValue<Affine>(L, 1);
  std::string s = "Transform(";
  for (int i = 0; i < 3; ++i) {
    s += i ? ", [" : "[";
    for (int j = 0; j < 4; ++j) s += (j ? " " : "") + formatNumber(a.m[i][j] + 0.0); // no "-0"
    s += "]";
  }
  s += ")";
  lua_pushlstring(L, s.data(), s.size());
  return 1;
}

} // namespace

void registerValueClasses(Registry &reg) {
  reg.cls<Vec3>("Vector")
      .ctor(+[](Vec3 &v, double x, double y, double z) { v = {x, y, z}; })
      .readonly("x", &Vec3::x)
      .readonly("y", &Vec3::y)
      .readonly("z", &Vec3::z)
      .method("dot", +[](const Vec3 &a, const Vec3 &b) { return dot(a, b); })
      .method("cross", +[](const Vec3 &a, const Vec3 &b) { return cross(a, b); })
      .method("length", +[](const Vec3 &v) { return length(v); })
      .method("normalized", +[](const Vec3 &v) {
        if (!(length(v) > 0)) throw ScriptError("Vector:normalized: the vector has zero length");
        return normalize(v);
      })
      .op("__add", +[](const Vec3 &a, const Vec3 &b) { return a + b; })
      .op("__sub", +[](const Vec3 &a, const Vec3 &b) { return a - b; })
      .op("__unm", +[](const Vec3 &a, const Vec3 &) { return -a; }) // Lua passes the operand twice
      .meta("__mul", &vectorMul)
      .op("__div", +[](const Vec3 &a, double s) {
        if (s == 0) throw ScriptError("Vector: division by zero");
        return a / s;
      })
      .meta("__eq", &valueEq<Vec3>)
      .meta("__tostring", &vectorToString);

  reg.cls<Color>("Color")
      .ctor(+[](Color &c, double r, double g, double b) { c = {r, g, b}; })
      .readonly("r", &Color::r)
      .readonly("g", &Color::g)
      .readonly("b", &Color::b)
      .op("__add", +[](const Color &a, const Color &b) { return a + b; })
      .meta("__mul", &colorMul)
      .meta("__eq", &valueEq<Color>)
      .meta("__tostring", &colorToString);

  reg.cls<Affine>("Transform")
      .method("inverse", +[](const Affine &t) { return Affine::from(t.toTransform().inverse()); })
      .op("__mul", +[](const Affine &a, const Affine &b) {
        return checked(a * b, "Transform: the product is singular");
      })
      .meta("__eq", &valueEq<Affine>)
      .meta("__tostring", &transformToString);

  reg.function("Translate", +[](const Vec3 &v) {
    Affine a;
    a.m[0][3] = v.x;
    a.m[1][3] = v.y;
    a.m[2][3] = v.z;
    return checked(a, "Translate: the vector is not finite");
  });
  reg.function("Scale", +[](double sx, std::optional<double> sy, std::optional<double> sz) {
    if (sy.has_value() != sz.has_value())
      throw ScriptError("Scale: takes one number (uniform) or three (sx, sy, sz)");
    Affine a;
    a.m[0][0] = sx;
    a.m[1][1] = sy.value_or(sx);
    a.m[2][2] = sz.value_or(sx);
    const double sy1 = sy.value_or(sx), sz1 = sz.value_or(sx);
    if (sx == 0 || sy1 == 0 || sz1 == 0)
      return checked(a, "Scale: the transform is singular (a scale factor is zero)");
    return checked(a, "Scale(" + readableNumber(sx) + ", " + readableNumber(sy1) + ", " +
                          readableNumber(sz1) +
                          "): the factors are too large or too small to invert (their product "
                          "is out of a double's range)");
  });
  reg.function("Rotate", +[](const Vec3 &axis, double degrees) {
    return checked(Transform::rotate(axis, degrees), "Rotate: the axis has zero length");
  });
  reg.function("LookAt", +[](const Vec3 &pos, const Vec3 &at, const Vec3 &up) {
    return checked(Transform::lookAt(pos, at, up),
                   "LookAt: up is parallel to at - pos (or at equals pos)");
  });
  reg.function("Identity", +[]() { return Affine(); });
}

} // namespace lray::lua
