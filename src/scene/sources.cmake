list(APPEND LRAY_CORE_SOURCES src/scene/mesh_builder.cpp src/scene/obj_loader.cpp
     src/scene/pigment_uv.cpp src/scene/scene_checks.cpp)
