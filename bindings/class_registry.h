// Pipeline: script -> scene description. The classes registered into one
// lua_State: each Lua class's metatable references, its members and its
// C++ type, and the default class of each C++ type (lua_binding.h builds
// them; BindingContext holds this registry).
#pragma once

#include <lua.hpp>

#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace lray::lua {

struct ClassInfo;
struct Member;

/// A small dense number per C++ type (for O(1) per-state lookups).
int nextTypeIndex();
template <class T> int typeIndex() {
  static const int index = nextTypeIndex();
  return index;
}

/// One unique address per C++ type.
template <class T> const void *typeTag() {
  static const char tag = 0;
  return &tag;
}

using Getter = void (*)(lua_State *, void *obj, int self, const Member &);
using Setter = void (*)(lua_State *, void *obj, int self, int value, const Member &);

/// An attribute: type-erased getter/setter plus the member pointer they use.
struct Member {
  std::string name;
  const ClassInfo *owner = nullptr;
  Getter get = nullptr;
  Setter set = nullptr; ///< null: read-only
  alignas(8) unsigned char pointer[16]{}; ///< member pointer or accessor functions
  alignas(8) unsigned char extra[16]{};   ///< validator function, if any
  int slot = 0;                           ///< user value slot of an object reference
};

/// A registered Lua class. Several classes may share one C++ type (all
/// pigments are PigmentObj); the first registered is the type's default
/// class, used when a reference attribute is read before it was assigned.
struct ClassInfo {
  std::string name;
  const void *typeTag = nullptr;
  size_t size = 0;
  int userValues = 0;
  int metatableRef = LUA_NOREF;
  int membersRef = LUA_NOREF;
  void (*construct)(void *payload) = nullptr; ///< placement-new + class defaults
  void (*destroy)(void *payload) = nullptr;   ///< null when trivially destructible
  /// Class defaults (e.g. Wood's frequency): `applyDefaults` calls the
  /// typed function stored in `defaultsFn`.
  void (*applyDefaults)(const ClassInfo &, void *payload) = nullptr;
  alignas(8) unsigned char defaultsFn[sizeof(void (*)())]{};
  std::deque<Member> members;
  std::vector<std::string> memberNames; ///< attributes and methods, for "did you mean"
};

/// Every class of one lua_State, owned here for the state's lifetime (its
/// closures point at them).
class ClassRegistry {
public:
  /// The default class of C++ type `tag` (first registered); asserts it exists.
  const ClassInfo &primary(const void *tag) const;
  /// Same, by typeIndex<T>() (the hot path: every Vector or Transform result).
  template <class T> const ClassInfo &primary() {
    size_t i = static_cast<size_t>(typeIndex<T>());
    if (i >= primaryByIndex.size()) primaryByIndex.resize(i + 1, nullptr);
    if (!primaryByIndex[i]) primaryByIndex[i] = &primary(typeTag<T>());
    return *primaryByIndex[i];
  }

  std::vector<std::unique_ptr<ClassInfo>> classes;
  std::unordered_map<const void *, const ClassInfo *> primaryByType;
  std::vector<const ClassInfo *> primaryByIndex; ///< cache of primaryByType by typeIndex
  std::deque<std::string> functionNames; ///< stable storage for error contexts
};

} // namespace lray::lua
