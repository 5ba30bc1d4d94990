# kd-tree backend tests (src/accel/kdtree).
list(APPEND LRAY_TEST_SOURCES
  tests/kdtree/kd_tree_test.cpp
  tests/kdtree/kdtree_accelerator_test.cpp
  tests/kdtree/sah_cost_model_test.cpp
  tests/kdtree/triangle_clip_test.cpp
  tests/kdtree/triangle_prefilter_test.cpp
  tests/kdtree/watertight_triangle_test.cpp)
