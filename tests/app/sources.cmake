list(APPEND LRAY_TEST_SOURCES tests/app/cli_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/app/farm_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/app/frame_writer_test.cpp)
list(APPEND LRAY_TEST_SOURCES tests/app/watch_test.cpp)
# The preview module's request framing is plain code: tested here directly.
list(APPEND LRAY_TEST_SOURCES tests/app/http_framing_test.cpp src/app/watch/http_framing.cpp)
