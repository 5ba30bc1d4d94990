# LRay's render time against raw Embree on the same rays (issue 34).
add_executable(bench_throughput bench/throughput/bench_throughput.cpp)
target_link_libraries(bench_throughput PRIVATE lray_core lray_warnings)
