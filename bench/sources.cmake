# Each area's benchmarks live in bench/<area>/ with their own sources.cmake.
foreach(area scene geometry kdtree render throughput)
  include(bench/${area}/sources.cmake OPTIONAL)
endforeach()
