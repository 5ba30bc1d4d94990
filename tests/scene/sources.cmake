list(APPEND LRAY_TEST_SOURCES tests/scene/obj_loader_test.cpp tests/scene/mesh_builder_test.cpp)
