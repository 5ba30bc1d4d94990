# Run at build time (POST_BUILD of lray_tests): lists the GoogleTest suites
# of TEST_EXECUTABLE and writes CTEST_FILE with one CTest test per suite.
# (One process per test, as gtest_discover_tests does, costs ~0.4 s of CPU
# each here: 3/4 of it in the dynamic loader resolving the ~260 shared
# libraries OpenImageIO brings in. Per suite keeps the granularity at a
# fraction of the cost.)
execute_process(COMMAND ${TEST_EXECUTABLE} --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed: ${status}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(content "")
foreach(line IN LISTS lines)
  # Suite lines start in column 0 and end with '.', maybe followed by a comment.
  if(line MATCHES "^([^ #][^ ]*)\\.( *#.*)?$")
    set(suite "${CMAKE_MATCH_1}")
    # The robustness suite (tests/stress, suites named Stress*, possibly
    # behind a parameter prefix such as Backends/) has its own label.
    set(label ${LABEL})
    if(suite MATCHES "(^|/)Stress")
      set(label stress)
    endif()
    # tests/hostile: scene files and options a hostile author could give.
    if(suite MATCHES "(^|/)Hostile")
      set(label hostile)
    endif()
    string(APPEND content
      "add_test([=[${suite}]=] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${suite}.*]==])\n"
      "set_tests_properties([=[${suite}]=] PROPERTIES LABELS ${label} TIMEOUT 600)\n")
  endif()
endforeach()
file(WRITE "${CTEST_FILE}" "${content}")
