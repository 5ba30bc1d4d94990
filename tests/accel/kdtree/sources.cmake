# kd-tree backend tests (src/accel/kdtree).
list(APPEND LRAY_TEST_SOURCES
  tests/accel/kdtree/flat_instances_test.cpp
  tests/accel/kdtree/kd_tree_test.cpp
  tests/accel/kdtree/ray_fan_test.cpp
  tests/accel/kdtree/kdtree_accelerator_test.cpp
  tests/accel/kdtree/sah_cost_model_test.cpp
  tests/accel/kdtree/triangle_clip_test.cpp
  tests/accel/kdtree/triangle_prefilter_test.cpp
  tests/accel/kdtree/watertight_triangle_test.cpp)
