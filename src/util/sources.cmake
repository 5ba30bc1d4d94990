list(APPEND LRAY_CORE_SOURCES src/util/module_loader.cpp src/util/printable_text.cpp)
