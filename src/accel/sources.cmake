list(APPEND LRAY_CORE_SOURCES src/accel/accelerator.cpp)
include(src/accel/embree/sources.cmake)
include(src/accel/kdtree/sources.cmake)
list(REMOVE_DUPLICATES LRAY_CORE_SOURCES)
