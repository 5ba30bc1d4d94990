// Pipeline: script -> scene description. The non-template half of the
// binding layer: metatables, member lookup, bulk set, error messages.
#include "bindings/lua_binding.h"

#include "bindings/lua_allocator.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace lray::lua {

namespace {

const ClassInfo &upvalueClass(lua_State *L, int up) {
  return *static_cast<const ClassInfo *>(lua_touserdata(L, lua_upvalueindex(up)));
}

/// The object a metamethod of class `cls` was called on. Only a finalizer
/// (--unsafe) can still hold one whose C++ part is gone.
void *selfObject(lua_State *L, int self, const ClassInfo &cls) {
  ObjHeader *h = objHeader(L, self);
  if (!h) throw ScriptError(cls.name + ": this object was freed (a finalizer outlived it)");
  return payload(h);
}

std::string unknownMemberMessage(lua_State *L, const ClassInfo &cls, int key) {
  if (lua_type(L, key) != LUA_TSTRING)
    return cls.name + ": attributes are named by strings, got " + typeName(L, key);
  std::string name = lua_tostring(L, key);
  std::string message = cls.name + ": unknown attribute '" + name + "'";
  std::string suggestion = closestName(name, cls.memberNames);
  if (!suggestion.empty()) message += " (did you mean '" + suggestion + "'?)";
  return message;
}

// Looks up the member named by the value at `key`, leaving nothing on the stack.
// Returns null and sets *isMethod when it is a method.
const Member *findMember(lua_State *L, int membersUpvalue, int key, bool *isMethod) {
  lua_pushvalue(L, key);
  int type = lua_rawget(L, lua_upvalueindex(membersUpvalue));
  const Member *m = type == LUA_TLIGHTUSERDATA ? static_cast<const Member *>(lua_touserdata(L, -1))
                                               : nullptr;
  *isMethod = type == LUA_TFUNCTION;
  lua_pop(L, 1);
  return m;
}

void assignMember(lua_State *L, const ClassInfo &cls, const Member *m, bool isMethod, int self,
                  int key, int value) {
  if (!m) {
    if (isMethod)
      throw ScriptError(cls.name + ": cannot assign to method '" + lua_tostring(L, key) + "'");
    throw ScriptError(unknownMemberMessage(L, cls, key));
  }
  if (!m->set) throw ScriptError(cls.name + ": attribute '" + m->name + "' is read-only");
  int top = lua_gettop(L);
  try {
    m->set(L, selfObject(L, self, cls), self, value, *m);
  } catch (const TypeMismatch &e) {
    throw ScriptError(cls.name + ": attribute '" + m->name + "' expects " + e.expected + ", got " +
                      e.given);
  }
  lua_settop(L, top);
}

void assign(lua_State *L, const ClassInfo &cls, int self, int key, int value) {
  bool isMethod = false;
  const Member *m = findMember(L, 1, key, &isMethod);
  assignMember(L, cls, m, isMethod, self, key, value);
}

int indexThunk(lua_State *L) {
  return protectedCall(L, [&] {
    const ClassInfo &cls = upvalueClass(L, 2);
    lua_pushvalue(L, 2);
    int type = lua_rawget(L, lua_upvalueindex(1));
    if (type == LUA_TFUNCTION) return 1;
    if (type != LUA_TLIGHTUSERDATA) throw ScriptError(unknownMemberMessage(L, cls, 2));
    const Member &m = *static_cast<const Member *>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    m.get(L, selfObject(L, 1, cls), 1, m);
    return 1;
  });
}

int newindexThunk(lua_State *L) {
  return protectedCall(L, [&] {
    assign(L, upvalueClass(L, 2), 1, 2, 3);
    return 0;
  });
}

// obj { attr = value, ... }: sets each attribute and returns obj itself.
int bulkSetThunk(lua_State *L) {
  return protectedCall(L, [&] {
    const ClassInfo &cls = upvalueClass(L, 2);
    if (lua_gettop(L) != 2 || lua_type(L, 2) != LUA_TTABLE)
      throw ScriptError(cls.name + ": calling an object sets attributes in bulk and takes one " +
                        "table, got " +
                        (lua_gettop(L) < 2 ? std::string("nothing") : typeName(L, 2)));
    lua_pushnil(L);
    while (lua_next(L, 2) != 0) {
      int top = lua_gettop(L);
      assign(L, cls, 1, top - 1, top);
      lua_settop(L, top - 1); // keep the key for lua_next
    }
    lua_settop(L, 1);
    return 1;
  });
}

int tostringThunk(lua_State *L) {
  const ClassInfo &cls = upvalueClass(L, 1);
  lua_pushfstring(L, "%s: %p", cls.name.c_str(), lua_touserdata(L, 1));
  return 1;
}

int gcThunk(lua_State *L) {
  if (ObjHeader *h = objHeader(L, 1)) {
    if (h->cls->destroy) BindingContext::of(L).destroyObjectOf(h);
    h->magic = 0; // a resurrected reference can no longer be used
  }
  return 0;
}

size_t editDistance(const std::string &a, const std::string &b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

} // namespace

void assignAttribute(lua_State *L, const ClassInfo &cls, int self, int key, int value) {
  self = lua_absindex(L, self);
  key = lua_absindex(L, key);
  value = lua_absindex(L, value);
  lua_rawgeti(L, LUA_REGISTRYINDEX, cls.membersRef);
  lua_pushvalue(L, key);
  const int type = lua_rawget(L, -2);
  const Member *m = type == LUA_TLIGHTUSERDATA ? static_cast<const Member *>(lua_touserdata(L, -1))
                                               : nullptr;
  lua_pop(L, 2);
  assignMember(L, cls, m, type == LUA_TFUNCTION, self, key, value);
}

// ---- BindingContext --------------------------------------------------------------

bool BindingContext::sameSource(uint32_t id, const lua_Debug &ar) const {
  const SourceKey &key = sourceKeys[id];
  return key.source == ar.source && key.length == ar.srclen &&
         std::memcmp(key.head.data(), ar.source, key.head.size()) == 0 &&
         std::memcmp(key.tail.data(), ar.source + ar.srclen - key.tail.size(), key.tail.size()) ==
             0;
}

ScriptLoc BindingContext::currentLocation(lua_State *L) {
  constexpr size_t kHeadBytes = 64;
  lua_Debug ar;
  for (int level = 0; lua_getstack(L, level, &ar); ++level) {
    if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
    const auto line = static_cast<uint32_t>(ar.currentline);
    if (sameSource(lastSourceId_, ar)) return {lastSourceId_, line}; // the usual case
    if (preludeSource == ar.source || std::strcmp(ar.source, "=sandbox") == 0) continue;
    auto it = sourceIds.find(ar.source);
    if (it != sourceIds.end() && sameSource(it->second, ar)) {
      lastSourceId_ = it->second;
      return {lastSourceId_, line};
    }
    if (sourceNames.size() >= kMaxSources) {
      if (!manySourcesId_) {
        manySourcesId_ = static_cast<uint32_t>(sourceNames.size());
        sourceNames.emplace_back("a chunk loaded at run time");
        sourceKeys.push_back({nullptr, 0, {}, {}});
      }
      return {manySourcesId_, line};
    }
    const auto id = static_cast<uint32_t>(sourceNames.size());
    sourceNames.emplace_back(ar.short_src);
    const size_t ends = std::min(ar.srclen, kHeadBytes);
    sourceKeys.push_back({ar.source, ar.srclen, std::string(ar.source, ends),
                          std::string(ar.source + ar.srclen - ends, ends)});
    sourceIds[ar.source] = id;
    lastSourceId_ = id;
    return {id, line};
  }
  return {};
}

SourceLocation BindingContext::resolve(ScriptLoc loc) const {
  if (loc.source >= sourceNames.size()) return {};
  return {sourceNames[loc.source], static_cast<int>(loc.line)};
}

namespace {

void unlinkAndFree(BindingContext &ctx, HeapObject *o) {
  o->prev->next = o->next;
  o->next->prev = o->prev;
  const ClassInfo &cls = *o->cls;
  cls.destroy(o->object());
  ::operator delete(o);
  if (ctx.allocator) ctx.allocator->external()->bytes -= sizeof(HeapObject) + cls.size;
}

} // namespace

void BindingContext::linkObject(HeapObject *o) {
  o->prev = &liveObjects_;
  o->next = liveObjects_.next;
  liveObjects_.next->prev = o;
  liveObjects_.next = o;
}

void BindingContext::destroyObjectOf(const ObjHeader *h) {
  if (h->generation != objectGeneration) return; // destroyLiveObjects() freed it
  unlinkAndFree(*this, HeapObject::of(h->object));
}

void BindingContext::destroyLiveObjects() {
  // Never reads the userdata: they may have been freed.
  while (liveObjects_.next != &liveObjects_) unlinkAndFree(*this, liveObjects_.next);
  ++objectGeneration;
}

// ---- objects and messages --------------------------------------------------------

void *pushNewObject(lua_State *L, const ClassInfo &cls) {
  const size_t inlineBytes = cls.destroy ? 0 : cls.size;
  void *mem = lua_newuserdatauv(L, kPayloadOffset + inlineBytes, cls.userValues);
  auto *h = static_cast<ObjHeader *>(mem);
  h->magic = 0;
  h->cls = &cls;
  h->generation = 0;
  if (!cls.destroy) {
    h->object = static_cast<char *>(mem) + kPayloadOffset;
  } else {
    BindingContext &ctx = BindingContext::of(L);
    // Charged like the Lua heap: a script cannot hold more than its limit
    // in objects whose bulk lives outside it.
    ctx.checkMemory(L, cls.name.c_str());
    auto *o = static_cast<HeapObject *>(::operator new(sizeof(HeapObject) + cls.size));
    o->cls = &cls;
    try {
      cls.construct(o->object());
    } catch (...) {
      ::operator delete(o);
      throw;
    }
    ctx.linkObject(o);
    h->object = o->object();
    h->generation = ctx.objectGeneration;
    if (ctx.allocator) ctx.allocator->external()->bytes += sizeof(HeapObject) + cls.size;
  }
  if (!cls.destroy) cls.construct(h->object);
  void *p = h->object;
  h->magic = kObjMagic;
  if (cls.applyDefaults) cls.applyDefaults(cls, p);
  lua_rawgeti(L, LUA_REGISTRYINDEX, cls.metatableRef);
  lua_setmetatable(L, -2);
  return p;
}

std::string typeName(lua_State *L, int i) {
  if (ObjHeader *h = objHeader(L, i)) return h->cls->name;
  if (lua_type(L, i) == LUA_TUSERDATA && luaL_getmetafield(L, i, "__name") != LUA_TNIL) {
    std::string name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "userdata";
    lua_pop(L, 1);
    return name;
  }
  return luaL_typename(L, i);
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.14g", v);
  return buf;
}

std::string describeValue(lua_State *L, int i) {
  switch (lua_type(L, i)) {
  case LUA_TNUMBER:
    if (lua_isinteger(L, i)) return std::to_string(lua_tointeger(L, i));
    return formatNumber(lua_tonumber(L, i));
  case LUA_TBOOLEAN:
    return lua_toboolean(L, i) ? "true" : "false";
  case LUA_TSTRING: {
    std::string s = lua_tostring(L, i);
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return "'" + s + "'";
  }
  default:
    return typeName(L, i);
  }
}

std::string closestName(const std::string &word, const std::vector<std::string> &names) {
  std::string best;
  // Close enough to be a typo: at most a third of the word, never all of it.
  size_t bestDistance = std::max<size_t>(1, word.size() / 3) + 1;
  for (const std::string &name : names) {
    size_t d = editDistance(word, name);
    if (d < bestDistance && d < word.size()) {
      bestDistance = d;
      best = name;
    }
  }
  return best;
}

void pushErrorMessage(lua_State *L, const char *message) {
  BindingContext &ctx = BindingContext::of(L);
  SourceLocation loc = ctx.resolve(ctx.currentLocation(L));
  if (loc.line > 0)
    lua_pushfstring(L, "%s: %s", loc.str().c_str(), message);
  else
    lua_pushstring(L, message);
}

std::string &pendingErrorText() {
  thread_local std::string text;
  return text;
}

void throwArgumentError(const char *context, int index, const TypeMismatch &e) {
  if (index <= 0)
    throw ScriptError(std::string(context) + ": self " + e.what() + " (call methods with ':')");
  throw ScriptError(std::string(context) + ": argument " + std::to_string(index) + " " + e.what());
}

void throwArgumentCount(const char *context, int maxArgs, int given) {
  throw ScriptError(std::string(context) + ": too many arguments (takes at most " +
                    std::to_string(maxArgs) + ", got " + std::to_string(given) + ")");
}

int rawFunctionThunk(lua_State *L) {
  return protectedCall(L, [&] { return upvalueFunction<RawFunction>(L, 1)(L); });
}

// ---- registration ----------------------------------------------------------------

ClassInfo &createClass(lua_State *L, const std::string &name, const void *tag, size_t size,
                       void (*construct)(void *), void (*destroy)(void *)) {
  BindingContext &ctx = BindingContext::of(L);
  auto owned = std::make_unique<ClassInfo>();
  ClassInfo &cls = *owned;
  ctx.classes.push_back(std::move(owned));
  cls.name = name;
  cls.typeTag = tag;
  cls.size = size;
  cls.construct = construct;
  cls.destroy = destroy;
  ctx.primaryByType.emplace(tag, &cls);

  lua_newtable(L); // members
  lua_pushvalue(L, -1);
  cls.membersRef = luaL_ref(L, LUA_REGISTRYINDEX);

  lua_newtable(L); // metatable
  lua_pushstring(L, name.c_str());
  lua_setfield(L, -2, "__name");
  lua_pushstring(L, name.c_str());
  lua_setfield(L, -2, "__metatable"); // scripts cannot swap it
  lua_pushvalue(L, -2);
  lua_pushlightuserdata(L, &cls);
  lua_pushcclosure(L, &indexThunk, 2);
  lua_setfield(L, -2, "__index");
  lua_pushvalue(L, -2);
  lua_pushlightuserdata(L, &cls);
  lua_pushcclosure(L, &newindexThunk, 2);
  lua_setfield(L, -2, "__newindex");
  lua_pushvalue(L, -2);
  lua_pushlightuserdata(L, &cls);
  lua_pushcclosure(L, &bulkSetThunk, 2);
  lua_setfield(L, -2, "__call");
  lua_pushlightuserdata(L, &cls);
  lua_pushcclosure(L, &tostringThunk, 1);
  lua_setfield(L, -2, "__tostring");
  if (destroy) {
    lua_pushcfunction(L, &gcThunk);
    lua_setfield(L, -2, "__gc");
  }
  cls.metatableRef = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_pop(L, 1); // members
  return cls;
}

void addMemberEntry(lua_State *L, ClassInfo &cls, Member &m) {
  m.owner = &cls;
  cls.memberNames.push_back(m.name);
  lua_rawgeti(L, LUA_REGISTRYINDEX, cls.membersRef);
  lua_pushlightuserdata(L, &m);
  lua_setfield(L, -2, m.name.c_str());
  lua_pop(L, 1);
}

void addMethodEntry(lua_State *L, ClassInfo &cls, const std::string &name) {
  cls.memberNames.push_back(name);
  lua_rawgeti(L, LUA_REGISTRYINDEX, cls.membersRef);
  lua_insert(L, -2);
  lua_setfield(L, -2, name.c_str());
  lua_pop(L, 1);
}

void setMetaEntry(lua_State *L, ClassInfo &cls, const char *event) {
  lua_rawgeti(L, LUA_REGISTRYINDEX, cls.metatableRef);
  lua_insert(L, -2);
  lua_setfield(L, -2, event);
  lua_pop(L, 1);
}

void pushName(lua_State *L, const std::string &name) {
  BindingContext &ctx = BindingContext::of(L);
  ctx.functionNames.push_back(name);
  lua_pushlightuserdata(L, &ctx.functionNames.back());
}

} // namespace lray::lua
