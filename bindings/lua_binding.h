// Pipeline: script -> scene description. A small declarative binding layer
// on the Lua 5.4 C API (in the spirit of LuaBridge3, written for LRay):
// C++ objects live inside userdata, classes are registered one line per
// constructor, attribute, method and operator, and every C++ exception
// thrown by bound code reaches the script as a Lua error prefixed with the
// script's "file:line: ".
//
//   reg.cls<FinishObj>("Finish")
//       .ctor(+[](FinishObj &) {})
//       .attr("diffuse", &Finish::diffuse)
//       .method("copy", +[](const FinishObj &f) { ... });
//
// Object references between userdata (a Texture's finish) are kept alive by
// Lua user values: the C++ field holds the raw pointer, user value `slot`
// holds the userdata, so the getter returns the very same Lua object.
#pragma once

#include "bindings/affine.h"
#include "bindings/class_registry.h"
#include "bindings/lua_allocator.h"
#include "bindings/read_log.h"
#include "bindings/sandbox_policy.h"
#include "math/color.h"
#include "math/transform.h"
#include "math/vec3.h"
#include "util/scene_error.h"

#include <lua.hpp>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace lray::lua {

/// A script mistake found by bound C++ code; the message has no location
/// (the call wrapper prefixes "file:line: ").
struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A value of the wrong type; the wrapper names the attribute or argument.
struct TypeMismatch : std::runtime_error {
  TypeMismatch(std::string expected_, std::string given_)
      : std::runtime_error("expects " + expected_ + ", got " + given_),
        expected(std::move(expected_)), given(std::move(given_)) {}
  std::string expected, given;
};

/// Compact script location stored inside objects (4 + 4 bytes instead of a
/// string per object): index into BindingContext::sourceNames and line.
struct ScriptLoc {
  uint32_t source = 0;
  uint32_t line = 0;
};

/// Types registered as Lua classes with reference semantics declare
/// `static constexpr const char *kLuaName` (used in "expects ..." messages).
template <class T>
concept LuaObject = requires { T::kLuaName; };

/// Every userdata made by this layer starts with this header; the magic
/// number tells it apart from foreign userdata (io file handles). `object`
/// is the C++ object: right after the header for trivially destructible
/// classes, on the C++ heap for the others (BindingContext owns those, so
/// a userdata Lua frees without running its finalizer leaves nothing to
/// read or leak); `generation` is BindingContext::objectGeneration when
/// the object was made.
struct ObjHeader {
  uint64_t magic;
  const ClassInfo *cls;
  void *object;
  uint64_t generation;
};

/// What precedes a heap-held object: its links in BindingContext's list of
/// live objects and its class.
struct HeapObject {
  HeapObject *prev, *next;
  const ClassInfo *cls;
  uint64_t pad; ///< keeps the object 16-byte aligned
  void *object() { return this + 1; }
  static HeapObject *of(void *object) { return static_cast<HeapObject *>(object) - 1; }
};
inline constexpr uint64_t kObjMagic = 0x4c52617955644f62ull;
inline constexpr size_t kPayloadOffset = sizeof(ObjHeader);

/// Per-lua_State data, reachable from any C function through the state's
/// extra space: the classes (ClassRegistry), what the script may do
/// (SandboxPolicy), the files it read (ReadLog), where its chunks come from
/// and the C++ objects it holds.
class BindingContext : public ClassRegistry, public SandboxPolicy {
public:
  explicit BindingContext(std::string baseDirectory) : SandboxPolicy(std::move(baseDirectory)) {
    sourceNames.emplace_back();
    sourceKeys.push_back({nullptr, 0, {}, {}});
  }
  /// Frees any object made after destroyLiveObjects() (by a finalizer that
  /// --unsafe allowed, during lua_close).
  ~BindingContext() { destroyLiveObjects(); }
  BindingContext(const BindingContext &) = delete;
  BindingContext &operator=(const BindingContext &) = delete;
  static BindingContext &of(lua_State *L) {
    return **static_cast<BindingContext **>(lua_getextraspace(L));
  }
  void attach(lua_State *L) { *static_cast<BindingContext **>(lua_getextraspace(L)) = this; }

  /// Location of the innermost user-script frame (prelude frames skipped).
  ScriptLoc currentLocation(lua_State *L);
  SourceLocation resolve(ScriptLoc loc) const;
  /// SandboxPolicy::readablePath, and the path noted in the read log: for
  /// every file the script reads (dofile, io.open, mesh_from_obj, images).
  std::string resolveReadPath(const std::string &file, const char *what) {
    std::string path = readablePath(file, what);
    readLog.note(path);
    return path;
  }

  /// Every path resolveReadPath gave out: what `lray --watch` watches.
  ReadLog readLog;
  /// The C++ objects of classes with a destructor live on the C++ heap, in
  /// this list, not in their userdata: Lua 5.4 can free a finalizable
  /// userdata without calling its finalizer (after an emergency collection
  /// at the memory limit postponed it, or when the finalizer call itself
  /// ran out of memory), so the userdata may be gone while its object is
  /// still here. destroyLiveObjects() destroys what finalizers did not.
  void linkObject(HeapObject *o);
  /// Destroys and frees every object still in the list; the userdata that
  /// held them are then of an older generation, and their finalizers
  /// (which may still run, in lua_close) leave them alone.
  void destroyLiveObjects();
  /// The finalizer's half: destroys `h`'s object unless destroyLiveObjects
  /// already did.
  void destroyObjectOf(const ObjHeader *h);
  uint64_t objectGeneration = 0;

  std::string preludeSource = "=prelude"; ///< chunk name of the prelude
  std::vector<std::string> sourceNames; ///< [0] = unknown
  /// How a chunk is recognised: the address of its source text, which Lua
  /// keeps while the chunk lives, checked against its length and first
  /// bytes in case a later chunk reuses the address. Never the whole text:
  /// a chunk loaded from a string has that string as its source.
  struct SourceKey {
    const char *source;
    size_t length;
    std::string head, tail; ///< the first and last (up to) 64 bytes
  };
  std::vector<SourceKey> sourceKeys; ///< by id
  std::unordered_map<const void *, uint32_t> sourceIds;
  /// Distinct chunks named at most (a script can load chunks without end);
  /// later ones share one name.
  static constexpr size_t kMaxSources = 4096;
  /// Where the script was when the hook last ran (every few thousand
  /// instructions): the place a memory error, which Lua reports without
  /// one, is blamed on.
  ScriptLoc lastSeen{};

private:
  HeapObject liveObjects_{&liveObjects_, &liveObjects_, nullptr, 0}; ///< list head
  uint32_t lastSourceId_ = 0; ///< one-entry cache for currentLocation
  uint32_t manySourcesId_ = 0; ///< the name shared past kMaxSources (0: not made yet)
  bool sameSource(uint32_t id, const lua_Debug &ar) const;
};

// ---- userdata access ---------------------------------------------------------

inline ObjHeader *objHeader(lua_State *L, int i) {
  if (lua_type(L, i) != LUA_TUSERDATA || lua_rawlen(L, i) < sizeof(ObjHeader)) return nullptr;
  auto *h = static_cast<ObjHeader *>(lua_touserdata(L, i));
  if (h->magic != kObjMagic) return nullptr;
  // Its object was freed by destroyLiveObjects() (a finalizer that --unsafe
  // allowed, running in lua_close, still holds the userdata).
  if (h->cls->destroy && h->generation != BindingContext::of(L).objectGeneration) return nullptr;
  return h;
}
inline void *payload(ObjHeader *h) { return h->object; }

/// The C++ object at stack index i if it is of type T, else null.
template <class T> T *toObject(lua_State *L, int i) {
  ObjHeader *h = objHeader(L, i);
  if (!h || h->cls->typeTag != typeTag<T>()) return nullptr;
  return static_cast<T *>(payload(h));
}

/// Pushes a new default-constructed object of class `cls`; returns it.
void *pushNewObject(lua_State *L, const ClassInfo &cls);
template <class T> T &pushNew(lua_State *L, const ClassInfo &cls) {
  return *static_cast<T *>(pushNewObject(L, cls));
}
template <class T> T &pushNew(lua_State *L) {
  return pushNew<T>(L, BindingContext::of(L).primary<T>());
}

/// "Vector", "number", "nil": what the value at i is, for messages.
std::string typeName(lua_State *L, int i);
/// Like typeName but numbers and strings show their value ("2.5", "'abc'").
std::string describeValue(lua_State *L, int i);
/// The closest of `names` to `word` by edit distance, or "" if none is close.
std::string closestName(const std::string &word, const std::vector<std::string> &names);
/// Formats a number the way messages and tostring show it.
std::string formatNumber(double v);

// ---- value conversion ----------------------------------------------------------

template <class T> struct LuaValue; // check(L, i) -> T, push(L, v), expected()

template <> struct LuaValue<double> {
  static const char *expected() { return "a number"; }
  static double check(lua_State *L, int i) {
    if (lua_type(L, i) != LUA_TNUMBER) throw TypeMismatch(expected(), typeName(L, i));
    double v = lua_tonumber(L, i);
    if (!std::isfinite(v)) throw TypeMismatch("a finite number", describeValue(L, i));
    return v;
  }
  static void push(lua_State *L, double v) { lua_pushnumber(L, v); }
};

template <> struct LuaValue<int> {
  static const char *expected() { return "an integer"; }
  static int check(lua_State *L, int i) {
    if (lua_type(L, i) != LUA_TNUMBER) throw TypeMismatch(expected(), typeName(L, i));
    double v = lua_tonumber(L, i);
    if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0)
      throw TypeMismatch(expected(), describeValue(L, i));
    return static_cast<int>(v);
  }
  static void push(lua_State *L, int v) { lua_pushinteger(L, v); }
};

template <> struct LuaValue<bool> {
  static const char *expected() { return "a boolean"; }
  static bool check(lua_State *L, int i) {
    if (lua_type(L, i) != LUA_TBOOLEAN) throw TypeMismatch(expected(), typeName(L, i));
    return lua_toboolean(L, i) != 0;
  }
  static void push(lua_State *L, bool v) { lua_pushboolean(L, v); }
};

template <> struct LuaValue<std::string> {
  static const char *expected() { return "a string"; }
  static std::string check(lua_State *L, int i) {
    if (lua_type(L, i) != LUA_TSTRING) throw TypeMismatch(expected(), typeName(L, i));
    size_t n = 0;
    const char *s = lua_tolstring(L, i, &n);
    return std::string(s, n);
  }
  static void push(lua_State *L, const std::string &v) { lua_pushlstring(L, v.data(), v.size()); }
};

/// Value classes (Vector, Color, Transform): copied in and out of userdata.
template <class T, const char *Expected> struct LuaValueClass {
  static const char *expected() { return Expected; }
  static T check(lua_State *L, int i) {
    if (T *p = toObject<T>(L, i)) return *p;
    throw TypeMismatch(expected(), typeName(L, i));
  }
  static void push(lua_State *L, const T &v) { pushNew<T>(L) = v; }
};
inline constexpr char kVectorExpected[] = "a Vector";
inline constexpr char kColorExpected[] = "a Color";
inline constexpr char kTransformExpected[] = "a Transform";
template <> struct LuaValue<Vec3> : LuaValueClass<Vec3, kVectorExpected> {};
template <> struct LuaValue<Color> : LuaValueClass<Color, kColorExpected> {};
/// Lua's Transform holds an Affine (see affine.h); a Transform-typed
/// attribute converts on the way in and out.
template <> struct LuaValue<Affine> : LuaValueClass<Affine, kTransformExpected> {};
template <> struct LuaValue<Transform> {
  static const char *expected() { return kTransformExpected; }
  static Transform check(lua_State *L, int i) {
    return LuaValue<Affine>::check(L, i).toTransform();
  }
  static void push(lua_State *L, const Transform &t) { LuaValue<Affine>::push(L, Affine::from(t)); }
};

/// Optional trailing arguments: nil or absent gives nullopt.
template <class T> struct LuaValue<std::optional<T>> {
  static const char *expected() { return LuaValue<T>::expected(); }
  static std::optional<T> check(lua_State *L, int i) {
    if (lua_isnoneornil(L, i)) return std::nullopt;
    return LuaValue<T>::check(L, i);
  }
};

/// Object references as function arguments / attribute values.
template <LuaObject T> T &checkObject(lua_State *L, int i) {
  if (T *p = toObject<T>(L, i)) return *p;
  throw TypeMismatch(T::kLuaName, typeName(L, i));
}

/// The object or value at i by reference (for self arguments of raw functions).
template <class T> T &checkObjectValue(lua_State *L, int i) {
  if (T *p = toObject<T>(L, i)) return *p;
  if constexpr (LuaObject<T>)
    throw TypeMismatch(T::kLuaName, typeName(L, i));
  else
    throw TypeMismatch(LuaValue<T>::expected(), typeName(L, i));
}

/// Self (index 1) of a raw method; `context` is "Class:method" for the message.
template <class T> T &checkSelf(lua_State *L, const char *context);

template <class A> decltype(auto) checkArg(lua_State *L, int i) {
  using Raw = std::remove_cvref_t<A>;
  if constexpr (std::is_lvalue_reference_v<A> && !std::is_const_v<std::remove_reference_t<A>>) {
    return checkObjectValue<Raw>(L, i); // a mutable self: the object inside the userdata
  } else if constexpr (LuaObject<Raw>) {
    static_assert(std::is_lvalue_reference_v<A>, "objects are passed by reference");
    return checkObject<Raw>(L, i);
  } else {
    return LuaValue<Raw>::check(L, i);
  }
}

template <class R> void pushResult(lua_State *L, R &&r) {
  LuaValue<std::remove_cvref_t<R>>::push(L, std::forward<R>(r));
}

// ---- call protection -----------------------------------------------------------

/// Pushes "file:line: message" using the innermost user-script frame.
void pushErrorMessage(lua_State *L, const char *message);

/// While C++ code of the binding layer runs, the script's memory limit does
/// not refuse allocations: a refusal is a Lua memory error, whose longjmp
/// would skip the destructors of the call's C++ objects (a leak a script
/// could repeat in a loop, or worse). protectedCall checks the limit when
/// the C++ code is done instead; one call can overshoot it by what it
/// allocates itself. Nests; ScriptState clears it before each script call
/// (a longjmp out of a call that true out-of-memory caused skips the end).
class DeferredMemoryLimit {
public:
  explicit DeferredMemoryLimit(BindingContext &ctx) : allocator_(ctx.allocator) {
    if (allocator_) allocator_->deferLimit();
  }
  ~DeferredMemoryLimit() {
    if (allocator_) allocator_->restoreLimit();
  }
  DeferredMemoryLimit(const DeferredMemoryLimit &) = delete;
  DeferredMemoryLimit &operator=(const DeferredMemoryLimit &) = delete;
  /// The limit's message if the script's memory is past it even after a
  /// full collection, else empty.
  std::string exceeded(lua_State *L) const {
    return BindingContext::of(L).pastMemoryLimit(L) ? allocator_->limitMessage() : std::string();
  }

private:
  LuaAllocator *allocator_;
};

/// Where protectedCall keeps an error's text between its catch block and
/// the push (a longjmp out of a catch block would corrupt the C++ runtime's
/// exception state).
std::string &pendingErrorText();

/// Runs f(); a C++ exception, or the script's memory past its limit after
/// f() returned, becomes a Lua error. lua_error is called only after every
/// C++ object of the call is destroyed (Lua longjmps), and nothing in
/// between can raise a Lua error (see DeferredMemoryLimit).
template <class F> int protectedCall(lua_State *L, F &&f) {
  {
    DeferredMemoryLimit deferred(BindingContext::of(L));
    std::string &error = pendingErrorText();
    try {
      const int results = f();
      error = deferred.exceeded(L);
      if (error.empty()) return results;
    } catch (const std::bad_alloc &) {
      error.clear(); // only what cannot fail here
    } catch (const std::exception &e) {
      try {
        error = e.what();
      } catch (const std::bad_alloc &) {
        error.clear();
      }
    }
    if (error.empty())
      lua_pushliteral(L, "out of memory");
    else
      pushErrorMessage(L, error.c_str());
    // Where a memory error is blamed should raising this one meet the
    // limit (the message handler's own call can): here, not where the
    // instruction hook last looked.
    BindingContext &ctx = BindingContext::of(L);
    ctx.lastSeen = ctx.currentLocation(L);
  }
  return lua_error(L);
}

/// Wraps a TypeMismatch from argument `index` as "context: argument n expects ..".
[[noreturn]] void throwArgumentError(const char *context, int index, const TypeMismatch &e);
[[noreturn]] void throwArgumentCount(const char *context, int maxArgs, int given);

template <class T> T &checkSelf(lua_State *L, const char *context) {
  try {
    return checkObjectValue<T>(L, 1);
  } catch (const TypeMismatch &e) {
    throwArgumentError(context, 0, e);
  }
}

template <class R, class... A, size_t... I>
int invokeTyped(lua_State *L, R (*f)(A...), int first, int shown, const char *context,
                std::index_sequence<I...>) {
  int given = lua_gettop(L) - first + 1;
  if (given > static_cast<int>(sizeof...(A)))
    throwArgumentCount(context, static_cast<int>(sizeof...(A)) - (first - shown),
                       given - (first - shown));
  // Check every argument first (left to right) so messages name the first bad one.
  auto check = [&](auto tag, int index) -> decltype(auto) {
    using Arg = typename decltype(tag)::type;
    try {
      return checkArg<Arg>(L, index);
    } catch (const TypeMismatch &e) {
      throwArgumentError(context, index - first + shown, e);
    }
  };
  std::tuple<decltype(check(std::type_identity<A>{}, 0))...> args{
      check(std::type_identity<A>{}, first + static_cast<int>(I))...};
  if constexpr (std::is_void_v<R>) {
    f(std::get<I>(args)...);
    return 0;
  } else {
    pushResult(L, f(std::get<I>(args)...));
    return 1;
  }
}

/// Calls init(self, args...) with the arguments at stack 2..N+1 (the new
/// object sits at 1 and is not re-checked).
template <class T, class... A, size_t... I>
void invokeInit(lua_State *L, void (*init)(T &, A...), T &self, const char *context,
                std::index_sequence<I...>) {
  int given = lua_gettop(L) - 1;
  if (given > static_cast<int>(sizeof...(A)))
    throwArgumentCount(context, static_cast<int>(sizeof...(A)), given);
  auto check = [&](auto tag, int index) -> decltype(auto) {
    using Arg = typename decltype(tag)::type;
    try {
      return checkArg<Arg>(L, index);
    } catch (const TypeMismatch &e) {
      throwArgumentError(context, index - 1, e);
    }
  };
  std::tuple<decltype(check(std::type_identity<A>{}, 0))...> args{
      check(std::type_identity<A>{}, 2 + static_cast<int>(I))...};
  init(self, std::get<I>(args)...);
}

// ---- closures ------------------------------------------------------------------

template <class Fn> void pushFunctionPointer(lua_State *L, Fn f) {
  void *mem = lua_newuserdatauv(L, sizeof(Fn), 0);
  std::memcpy(mem, &f, sizeof(Fn));
}
template <class Fn> Fn upvalueFunction(lua_State *L, int up) {
  Fn f;
  std::memcpy(&f, lua_touserdata(L, lua_upvalueindex(up)), sizeof(Fn));
  return f;
}
inline const char *upvalueName(lua_State *L, int up) {
  return static_cast<const std::string *>(lua_touserdata(L, lua_upvalueindex(up)))->c_str();
}

/// A typed free function: upvalue 1 = pointer, 2 = name.
template <class R, class... A> int typedFunctionThunk(lua_State *L) {
  return protectedCall(L, [&] {
    auto f = upvalueFunction<R (*)(A...)>(L, 1);
    return invokeTyped(L, f, 1, 1, upvalueName(L, 2), std::index_sequence_for<A...>{});
  });
}

/// A typed method: argument 1 is self and not counted in messages.
template <class R, class... A> int typedMethodThunk(lua_State *L) {
  return protectedCall(L, [&] {
    auto f = upvalueFunction<R (*)(A...)>(L, 1);
    return invokeTyped(L, f, 1, 0, upvalueName(L, 2), std::index_sequence_for<A...>{});
  });
}

/// A raw lua_CFunction-like implementation that may throw C++ exceptions.
using RawFunction = int (*)(lua_State *);
int rawFunctionThunk(lua_State *L);

// ---- attribute accessors -------------------------------------------------------

template <class M> using Validator = const char *(*)(const M &);

template <class T, class C, class M> M &memberRef(void *obj, const Member &m) {
  M C::*p;
  std::memcpy(&p, m.pointer, sizeof p);
  return static_cast<C &>(*static_cast<T *>(obj)).*p;
}

template <class T, class C, class M>
void getAttribute(lua_State *L, void *obj, int self, const Member &m) {
  M &field = memberRef<T, C, M>(obj, m);
  if constexpr (std::is_pointer_v<M>) {
    using U = std::remove_pointer_t<M>;
    if (field) {
      lua_getiuservalue(L, self, m.slot);
    } else {
      // Unassigned reference: materialise the default object now, so that
      // `t.finish.diffuse = 1` changes this texture's own finish.
      U &fresh = pushNew<U>(L);
      lua_pushvalue(L, -1);
      lua_setiuservalue(L, self, m.slot);
      memberRef<T, C, M>(obj, m) = &fresh;
    }
  } else {
    LuaValue<M>::push(L, field);
  }
}

/// The value at stack index `value` as an M, passed through the member's
/// validator (if any); TypeMismatch otherwise.
template <class M> M checkedValue(lua_State *L, int value, const Member &m) {
  M v = LuaValue<M>::check(L, value);
  Validator<M> validate;
  std::memcpy(&validate, m.extra, sizeof validate);
  if (validate) {
    if (const char *expected = validate(v)) throw TypeMismatch(expected, describeValue(L, value));
  }
  return v;
}

template <class T, class C, class M>
void setAttribute(lua_State *L, void *obj, int self, int value, const Member &m) {
  if constexpr (std::is_pointer_v<M>) {
    using U = std::remove_pointer_t<M>;
    U &target = checkObject<U>(L, value);
    lua_pushvalue(L, value);
    lua_setiuservalue(L, self, m.slot);
    memberRef<T, C, M>(obj, m) = &target;
  } else {
    memberRef<T, C, M>(obj, m) = checkedValue<M>(L, value, m);
  }
}

/// Attributes of a part of the object (an entity's shape parameters):
/// `Part(object)` returns the C that holds the field. Values only.
template <class T, auto Part, class C, class M> M &partMemberRef(void *obj, const Member &m) {
  M C::*p;
  std::memcpy(&p, m.pointer, sizeof p);
  return Part(*static_cast<T *>(obj)).*p;
}

template <class T, auto Part, class C, class M>
void getPartAttribute(lua_State *L, void *obj, int, const Member &m) {
  LuaValue<M>::push(L, partMemberRef<T, Part, C, M>(obj, m));
}

template <class T, auto Part, class C, class M>
void setPartAttribute(lua_State *L, void *obj, int, int value, const Member &m) {
  partMemberRef<T, Part, C, M>(obj, m) = checkedValue<M>(L, value, m);
}

template <class T> using PropertyGet = void (*)(lua_State *, T &, int self);
template <class T> using PropertySet = void (*)(lua_State *, T &, int self, int value);

template <class T> void getProperty(lua_State *L, void *obj, int self, const Member &m) {
  PropertyGet<T> g;
  std::memcpy(&g, m.pointer, sizeof g);
  g(L, *static_cast<T *>(obj), self);
}
template <class T> void setProperty(lua_State *L, void *obj, int self, int value, const Member &m) {
  PropertySet<T> s;
  std::memcpy(&s, m.extra, sizeof s);
  s(L, *static_cast<T *>(obj), self, value);
}

// ---- registration --------------------------------------------------------------

/// Creates the metatable for a new class; returns its ClassInfo.
ClassInfo &createClass(lua_State *L, const std::string &name, const void *tag, size_t size,
                       void (*construct)(void *), void (*destroy)(void *));
/// Adds a member entry (attribute) to the class's member table.
void addMemberEntry(lua_State *L, ClassInfo &cls, Member &m);
/// Adds a closure (method) to the class's member table; pops it.
void addMethodEntry(lua_State *L, ClassInfo &cls, const std::string &name);
/// Sets metatable[event] to the closure on top of the stack; pops it.
void setMetaEntry(lua_State *L, ClassInfo &cls, const char *event);
/// Pushes a full-userdata pointing at a stable copy of `name` (for messages).
void pushName(lua_State *L, const std::string &name);

/// Fluent builder for one class; each call registers one member.
template <class T> class ClassBuilder {
public:
  ClassBuilder(lua_State *L, ClassInfo &cls) : L_(L), cls_(cls) {}

  /// Defaults applied to every new instance (constructed or materialised).
  ClassBuilder &defaults(void (*init)(T &)) {
    static_assert(sizeof init == sizeof cls_.defaultsFn);
    std::memcpy(cls_.defaultsFn, &init, sizeof init);
    cls_.applyDefaults = +[](const ClassInfo &c, void *p) {
      void (*f)(T &);
      std::memcpy(&f, c.defaultsFn, sizeof f);
      f(*static_cast<T *>(p));
    };
    return *this;
  }

  /// The global constructor function named after the class.
  template <class... A> ClassBuilder &ctor(void (*init)(T &, A...)) {
    pushFunctionPointer(L_, init);
    lua_pushlightuserdata(L_, &cls_);
    lua_pushcclosure(L_, &constructorThunkImpl<A...>, 2);
    lua_setglobal(L_, cls_.name.c_str());
    return *this;
  }

  /// A typed attribute; `validate` returns the expected description on failure.
  template <class C, class M>
  ClassBuilder &attr(const char *name, M C::*field, Validator<M> validate = nullptr) {
    static_assert(std::is_base_of_v<C, T>);
    Member &m = cls_.members.emplace_back();
    m.name = name;
    m.get = &getAttribute<T, C, M>;
    m.set = &setAttribute<T, C, M>;
    static_assert(sizeof field <= sizeof m.pointer);
    std::memcpy(m.pointer, &field, sizeof field);
    if constexpr (std::is_pointer_v<M>) {
      m.slot = ++cls_.userValues;
    } else {
      std::memcpy(m.extra, &validate, sizeof validate);
    }
    addMemberEntry(L_, cls_, m);
    return *this;
  }

  /// A typed attribute of the part of T that `Part` (C &(*)(T &)) returns.
  template <auto Part, class C, class M>
  ClassBuilder &partAttr(const char *name, M C::*field, Validator<M> validate = nullptr) {
    static_assert(!std::is_pointer_v<M>, "object references are attributes of the object itself");
    Member &m = cls_.members.emplace_back();
    m.name = name;
    m.get = &getPartAttribute<T, Part, C, M>;
    m.set = &setPartAttribute<T, Part, C, M>;
    static_assert(sizeof field <= sizeof m.pointer);
    std::memcpy(m.pointer, &field, sizeof field);
    std::memcpy(m.extra, &validate, sizeof validate);
    addMemberEntry(L_, cls_, m);
    return *this;
  }

  /// A read-only typed attribute.
  template <class C, class M> ClassBuilder &readonly(const char *name, M C::*field) {
    attr(name, field);
    cls_.members.back().set = nullptr;
    return *this;
  }

  /// An attribute with hand-written accessors (Mesh arrays).
  ClassBuilder &property(const char *name, PropertyGet<T> get, PropertySet<T> set) {
    Member &m = cls_.members.emplace_back();
    m.name = name;
    m.get = &getProperty<T>;
    m.set = set ? &setProperty<T> : nullptr;
    std::memcpy(m.pointer, &get, sizeof get);
    std::memcpy(m.extra, &set, sizeof set);
    addMemberEntry(L_, cls_, m);
    return *this;
  }

  /// A typed method; the function's first parameter is self.
  template <class R, class S, class... A> ClassBuilder &method(const char *name, R (*f)(S, A...)) {
    pushFunctionPointer(L_, f);
    pushName(L_, cls_.name + ":" + name);
    lua_pushcclosure(L_, &typedMethodThunk<R, S, A...>, 2);
    addMethodEntry(L_, cls_, name);
    return *this;
  }

  /// A constructor that reads the Lua stack itself; upvalue 2 is this class.
  ClassBuilder &rawCtor(RawFunction f) {
    pushFunctionPointer(L_, f);
    lua_pushlightuserdata(L_, &cls_);
    lua_pushcclosure(L_, &rawFunctionThunk, 2);
    lua_setglobal(L_, cls_.name.c_str());
    return *this;
  }

  /// Reserves a user value slot for the binding code's own use (keep-alive lists).
  int userValueSlot() { return ++cls_.userValues; }

  /// A method that reads the Lua stack itself (self at index 1).
  ClassBuilder &rawMethod(const char *name, RawFunction f) {
    pushFunctionPointer(L_, f);
    lua_pushcclosure(L_, &rawFunctionThunk, 1);
    addMethodEntry(L_, cls_, name);
    return *this;
  }

  /// A metamethod ("__add", "__tostring", ...).
  ClassBuilder &meta(const char *event, RawFunction f) {
    pushFunctionPointer(L_, f);
    lua_pushcclosure(L_, &rawFunctionThunk, 1);
    setMetaEntry(L_, cls_, event);
    return *this;
  }

  /// A typed metamethod, e.g. op("__unm", +[](const Vec3 &v) { return -v; }).
  template <class R, class... A> ClassBuilder &op(const char *event, R (*f)(A...)) {
    pushFunctionPointer(L_, f);
    pushName(L_, cls_.name + " " + event);
    lua_pushcclosure(L_, &typedFunctionThunk<R, A...>, 2);
    setMetaEntry(L_, cls_, event);
    return *this;
  }

  ClassInfo &info() { return cls_; }

private:
  template <class... A> static int constructorThunkImpl(lua_State *L) {
    return protectedCall(L, [&] {
      auto init = upvalueFunction<void (*)(T &, A...)>(L, 1);
      const auto &cls = *static_cast<const ClassInfo *>(lua_touserdata(L, lua_upvalueindex(2)));
      T &obj = pushNew<T>(L, cls);
      if constexpr (requires { obj.loc; }) obj.loc = BindingContext::of(L).currentLocation(L);
      lua_rotate(L, 1, 1); // object at 1, arguments from 2
      invokeInit(L, init, obj, cls.name.c_str(), std::index_sequence_for<A...>{});
      lua_settop(L, 1);
      return 1;
    });
  }

  lua_State *L_;
  ClassInfo &cls_;
};

/// `obj.key = value` for the object at `self` of class `cls` (key a string),
/// with the same checks and messages: for constructors that take attributes
/// in their argument table.
void assignAttribute(lua_State *L, const ClassInfo &cls, int self, int key, int value);

/// Registers classes and global functions into one lua_State.
class Registry {
public:
  explicit Registry(lua_State *L) : L_(L) {}

  template <class T> ClassBuilder<T> cls(const std::string &name) {
    static_assert(alignof(T) <= 8, "Lua userdata is 8-byte aligned");
    void (*destroy)(void *) = nullptr;
    if constexpr (!std::is_trivially_destructible_v<T>)
      destroy = +[](void *p) { static_cast<T *>(p)->~T(); };
    ClassInfo &info = createClass(
        L_, name, typeTag<T>(), sizeof(T), +[](void *p) { new (p) T(); }, destroy);
    return ClassBuilder<T>(L_, info);
  }

  /// A typed global function.
  template <class R, class... A> Registry &function(const char *name, R (*f)(A...)) {
    pushFunctionPointer(L_, f);
    pushName(L_, name);
    lua_pushcclosure(L_, &typedFunctionThunk<R, A...>, 2);
    lua_setglobal(L_, name);
    return *this;
  }

  /// A global function that reads the Lua stack itself.
  Registry &rawFunction(const char *name, RawFunction f) {
    pushFunctionPointer(L_, f);
    lua_pushcclosure(L_, &rawFunctionThunk, 1);
    lua_setglobal(L_, name);
    return *this;
  }

private:
  lua_State *L_;
};

} // namespace lray::lua
