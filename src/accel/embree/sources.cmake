# The Embree backend (included from src/accel/sources.cmake).
list(APPEND LRAY_CORE_SOURCES src/accel/embree/embree_accelerator.cpp
  src/accel/embree/embree_rays.cpp)
