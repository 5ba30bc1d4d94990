list(APPEND LRAY_TEST_SOURCES tests/hostile/hostile_input_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/hostile/preview_server_load_test.cpp)
