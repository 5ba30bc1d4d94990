list(APPEND LRAY_TEST_SOURCES tests/run/options_test.cpp tests/run/run_plan_test.cpp
     tests/run/frame_pipeline_test.cpp tests/run/render_threads_test.cpp)
