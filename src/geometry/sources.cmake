list(APPEND LRAY_CORE_SOURCES
  src/geometry/sphere.cpp
  src/geometry/cylinder.cpp
  src/geometry/cone.cpp
  src/geometry/cube.cpp
  src/geometry/shape.cpp
  src/geometry/triangle_hit.cpp
  src/geometry/float_frame.cpp)
