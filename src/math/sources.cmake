list(APPEND LRAY_CORE_SOURCES src/math/transform.cpp src/math/transform_motion.cpp)
