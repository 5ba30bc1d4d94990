add_executable(bench_backends bench/render/bench_backends.cpp)
target_link_libraries(bench_backends PRIVATE lray_bench_common lray_warnings)
target_compile_definitions(bench_backends PRIVATE LRAY_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
