list(APPEND LRAY_CORE_SOURCES
  src/geometry/shapes/sphere.cpp
  src/geometry/shapes/sphere_bound.cpp
  src/geometry/shapes/cylinder.cpp
  src/geometry/shapes/cone.cpp
  src/geometry/shapes/cube.cpp
  src/geometry/shapes/plane.cpp
  src/geometry/shapes/torus.cpp
  src/geometry/csg_tree.cpp
  src/geometry/csg_ray.cpp
  src/geometry/shape.cpp
  src/geometry/triangle_hit.cpp
  src/geometry/triangle_hits.cpp
  src/geometry/float_frame.cpp)
# Its SIMD lanes never cross a call (see the file).
set_source_files_properties(src/geometry/triangle_hits.cpp PROPERTIES COMPILE_OPTIONS -Wno-psabi)
