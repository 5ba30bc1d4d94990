include(src/accel/embree/sources.cmake)
include(src/accel/kdtree/sources.cmake)
