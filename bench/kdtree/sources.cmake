# kd-tree benchmark: bench_kdtree. accelerator_bench.{h,cpp} measure any
# backend over a Scene and are meant to be reused by a side-by-side driver.
add_library(lray_bench_common STATIC bench/kdtree/accelerator_bench.cpp)
target_link_libraries(lray_bench_common PUBLIC lray_core PRIVATE lray_warnings)
add_executable(bench_kdtree bench/kdtree/bench_kdtree.cpp)
target_link_libraries(bench_kdtree PRIVATE lray_bench_common lray_warnings)
# bench_kd_rays: kd-tree vs Embree on bench/backends' triangle ray sets, in
# thread CPU time, with a digest of the kd-tree's results.
add_executable(bench_kd_rays bench/kdtree/bench_kd_rays.cpp)
target_link_libraries(bench_kd_rays PRIVATE lray_bench_common lray_warnings)
