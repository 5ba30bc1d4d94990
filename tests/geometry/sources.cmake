list(APPEND LRAY_TEST_SOURCES tests/geometry/shape_test.cpp tests/geometry/shape_random_test.cpp
  tests/geometry/triangle_hit_test.cpp tests/geometry/csg_test.cpp
  tests/geometry/csg_oracle_test.cpp tests/geometry/sphere_bound_test.cpp
  tests/geometry/sphere_lanes_test.cpp)
