# Embree backend benchmark: raw Embree against EmbreeAccelerator.
add_executable(bench_embree bench/geometry/bench_embree.cpp)
target_link_libraries(bench_embree PRIVATE lray_core embree lray_warnings)
