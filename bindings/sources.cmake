# Script -> scene description: the Lua binding layer, the LRay classes, the
# sandbox, the converter into the plain model, and the embedded prelude.
list(APPEND LRAY_CORE_SOURCES
  bindings/lua_allocator.cpp
  bindings/lua_binding.cpp
  bindings/class_registry.cpp
  bindings/sandbox_policy.cpp
  bindings/register_values.cpp
  bindings/register_textures.cpp
  bindings/register_entities.cpp
  bindings/register_csg.cpp
  bindings/register_scene.cpp
  bindings/sandbox.cpp
  bindings/scene_converter.cpp
  bindings/script_state.cpp
  bindings/script_watchdog.cpp
  bindings/scene_script.cpp
  ${CMAKE_BINARY_DIR}/generated/lray_prelude.cpp)

# Embed lua/prelude.lua as a C++ string; re-run CMake when it changes.
set(LRAY_PRELUDE_LUA ${CMAKE_SOURCE_DIR}/lua/prelude.lua)
file(READ ${LRAY_PRELUDE_LUA} LRAY_PRELUDE_TEXT)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${LRAY_PRELUDE_LUA})
file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/generated/lray_prelude.cpp @ONLY CONTENT [=[
// Generated from lua/prelude.lua by bindings/sources.cmake; do not edit.
namespace lray::lua {
extern const char kPreludeSource[];
const char kPreludeSource[] = R"lray_prelude(@LRAY_PRELUDE_TEXT@)lray_prelude";
} // namespace lray::lua
]=])
