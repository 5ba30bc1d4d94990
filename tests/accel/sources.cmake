list(APPEND LRAY_TEST_SOURCES
  tests/accel/embree_accelerator_test.cpp
  tests/accel/embree_robustness_test.cpp
  tests/accel/embree_rays_test.cpp
  tests/accel/backend_parity_test.cpp)
include(tests/accel/kdtree/sources.cmake)
