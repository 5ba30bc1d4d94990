list(APPEND LRAY_CORE_SOURCES
  src/geometry/sphere.cpp
  src/geometry/cylinder.cpp
  src/geometry/cone.cpp
  src/geometry/cube.cpp
  src/geometry/shape.cpp
  src/geometry/triangle_hit.cpp
  src/geometry/triangle_hits.cpp
  src/geometry/float_frame.cpp)
# Its SIMD lanes never cross a call (see the file).
set_source_files_properties(src/geometry/triangle_hits.cpp PROPERTIES COMPILE_OPTIONS -Wno-psabi)
