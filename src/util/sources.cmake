list(APPEND LRAY_CORE_SOURCES src/util/memory_budget.cpp src/util/module_loader.cpp
     src/util/printable_text.cpp src/util/cpu_features.cpp)
