# Embree backend benchmark: raw Embree against EmbreeAccelerator.
add_executable(bench_embree bench/geometry/bench_embree.cpp)
target_link_libraries(bench_embree PRIVATE lray_core embree lray_warnings)

# CSG: rays/s through CSG objects against the same solids as plain shapes.
add_executable(bench_csg bench/geometry/bench_csg.cpp)
target_link_libraries(bench_csg PRIVATE lray_core lray_warnings)
