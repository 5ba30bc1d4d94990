list(APPEND LRAY_TEST_SOURCES tests/util/cpu_features_test.cpp)
