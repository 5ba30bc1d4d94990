list(APPEND LRAY_TEST_SOURCES tests/app/cli_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/app/farm_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/app/watch_test.cpp)
