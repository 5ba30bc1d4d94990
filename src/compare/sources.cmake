# lray-compare (README.md, "Reference-image CI for your scenes"): a library
# of its own, linked with OpenImageIO, toml++ and Boost.Math, which lray
# itself never loads.
pkg_check_modules(TOMLPP REQUIRED IMPORTED_TARGET tomlplusplus)
find_package(Boost REQUIRED)
add_library(lray_compare STATIC
  src/compare/compare_image.cpp src/compare/ssim.cpp src/compare/noise_test.cpp
  src/compare/comparison.cpp src/compare/suite.cpp src/compare/case_render.cpp
  src/compare/junit_report.cpp src/compare/html_report.cpp src/compare/compare_tool.cpp)
target_include_directories(lray_compare PUBLIC ${CMAKE_SOURCE_DIR}/src)
target_link_libraries(lray_compare
  PUBLIC fmt::fmt
  PRIVATE lray_core PkgConfig::OIIO PkgConfig::TOMLPP Boost::headers CLI11::CLI11 lray_warnings)
target_link_libraries(lray_compare PUBLIC lray_sanitize)

add_executable(lray-compare src/app/compare_main.cpp)
target_link_libraries(lray-compare PRIVATE lray_compare lray_warnings)
add_dependencies(lray-compare lray)
