list(APPEND LRAY_CORE_SOURCES src/app/progress_bar.cpp src/app/frame_writer.cpp src/app/app.cpp
                              src/app/merge.cpp
                              src/app/watch/file_watcher.cpp src/app/watch/preview_state.cpp
                              src/app/watch/preview_server.cpp
                              src/app/watch/watch_loop.cpp)

# The preview page's server (cpp-httplib) as a module loaded only by
# --watch --serve (app/watch/preview_server.cpp).
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
add_library(lray_preview MODULE src/app/watch/preview_module.cpp src/app/watch/preview_page.cpp
                                src/app/watch/preview_routes.cpp src/app/watch/http_loop.cpp
                                src/app/watch/http_framing.cpp src/app/watch/preview_state.cpp)
target_include_directories(lray_preview PRIVATE ${CMAKE_SOURCE_DIR}/src)
target_link_libraries(lray_preview PRIVATE PkgConfig::HTTPLIB lray_warnings lray_sanitize)
set_source_files_properties(src/app/watch/preview_server.cpp PROPERTIES
  COMPILE_DEFINITIONS "LRAY_PREVIEW_MODULE=\"$<TARGET_FILE:lray_preview>\"")
