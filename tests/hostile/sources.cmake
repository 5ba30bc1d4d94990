list(APPEND LRAY_TEST_SOURCES tests/hostile/hostile_input_test.cpp)
