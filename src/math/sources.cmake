list(APPEND LRAY_CORE_SOURCES src/math/transform.cpp)
