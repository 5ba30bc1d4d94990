# bench_scene_build: 1,000,000 transformed spheres from Lua into the scene model.
add_executable(bench_scene_build bench/scene/bench_scene_build.cpp)
target_link_libraries(bench_scene_build PRIVATE lray_core lray_warnings)
