list(APPEND LRAY_TEST_SOURCES tests/bindings/values_test.cpp tests/bindings/classes_test.cpp
     tests/bindings/errors_test.cpp tests/bindings/lua_allocator_test.cpp
     tests/bindings/scene_converter_test.cpp tests/bindings/scene_script_test.cpp
     tests/bindings/language_reference_test.cpp tests/bindings/csg_binding_test.cpp)
