list(APPEND LRAY_TEST_SOURCES tests/math/transform_test.cpp tests/math/random_test.cpp
     tests/math/transform_motion_test.cpp tests/math/next_double_test.cpp)
