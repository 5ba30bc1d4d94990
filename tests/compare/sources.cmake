list(APPEND LRAY_TEST_SOURCES tests/compare/ssim_test.cpp tests/compare/noise_test_test.cpp
     tests/compare/render_compare_test.cpp tests/compare/compare_tool_test.cpp)
