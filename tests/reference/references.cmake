# Reference-image tests: one CTest test per scene and backend (label
# "reference"), each rendering one frame small and comparing it with
# tests/reference/<name>.png through OpenImageIO (see reference_check.cpp).
# Failure reports go to <build>/reference-report/index.html.
#
# Thresholds (idiff's fail / failpercent / hardfail), and why:
# - Embree against its own reference: the renderer is deterministic, so the
#   same build on the same machine reproduces the reference byte for byte.
#   We allow 1 LSB (fail 0.004 > 1/255) for libm differences between machines,
#   and no pixel beyond it (failpercent 0).
# - kd-tree against the same (Embree) reference, with the same thresholds:
#   both backends fill their hits through the same double-precision code
#   (fillTriangleHit solves a triangle's barycentrics again in double), so
#   they render identical images whenever they pick the same primitives;
#   every gallery scene is identical at full size. A scene may still pass
#   its own kd-tree failpercent as a 7th argument (a silhouette tie between
#   the float and double triangle tests), with the reason beside it in
#   scenes.cmake; README.md ("Accuracy, and the two backends") allows at most 0.01 %.
add_executable(lray_refcheck tests/reference/reference_check.cpp)
target_link_libraries(lray_refcheck PRIVATE lray_core CLI11::CLI11 PkgConfig::OIIO lray_warnings)

set(LRAY_REFERENCE_REPORT ${CMAKE_BINARY_DIR}/reference-report)

# lray_reference_test(NAME SCENE FRAME WIDTH HEIGHT SAMPLES [KDTREE_FAILPERCENT])
function(lray_reference_test name scene frame width height samples)
  set(kdtree_failpercent 0)
  if(ARGC GREATER 6)
    set(kdtree_failpercent ${ARGV6})
  endif()
  foreach(backend embree kdtree)
    if(backend STREQUAL "embree")
      set(thresholds --fail 0.004 --failpercent 0 --hardfail 1)
    else()
      set(thresholds --fail 0.004 --failpercent ${kdtree_failpercent} --hardfail 1)
    endif()
    add_test(NAME reference.${name}.${backend}
             COMMAND lray_refcheck ${CMAKE_SOURCE_DIR}/${scene}
                     ${CMAKE_SOURCE_DIR}/tests/reference/${name}.png
                     --name ${name}.${backend} --backend ${backend} --frame ${frame}
                     --width ${width} --height ${height} --samples ${samples}
                     --report-dir ${LRAY_REFERENCE_REPORT} ${thresholds})
    set_tests_properties(reference.${name}.${backend} PROPERTIES LABELS reference)
  endforeach()
endfunction()

include(tests/reference/scenes.cmake OPTIONAL)
