list(APPEND LRAY_CORE_SOURCES src/util/memory_budget.cpp src/util/module_loader.cpp
     src/util/printable_text.cpp src/util/cpu_features.cpp src/util/cpu_target.cpp)
# The start-up check of LRAY_NATIVE builds runs before anything else and must
# run on any x86-64 CPU: compiled for the baseline whatever the build's flags
# (the later -march wins).
if(LRAY_NATIVE_FLAGS)
  set_source_files_properties(src/util/cpu_features.cpp PROPERTIES
                              COMPILE_OPTIONS "-march=x86-64;-mtune=generic")
endif()
