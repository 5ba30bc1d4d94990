# The kd-tree backend (issue 6); included from src/accel/sources.cmake.
list(APPEND LRAY_CORE_SOURCES
  src/accel/kdtree/kd_tree_build.cpp
  src/accel/kdtree/triangle_clip.cpp
  src/accel/kdtree/triangle_prefilter_avx2.cpp
  src/accel/kdtree/kdtree_accelerator.cpp)
