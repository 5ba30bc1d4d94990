# Robustness suite (issue 8): scale/offset sweeps, quadric accuracy, grazing
# and degenerate rays, non-finite input, backend parity, fuzz regressions.
list(APPEND LRAY_TEST_SOURCES
  tests/stress/scale_sweep_test.cpp
  tests/stress/quadric_accuracy_test.cpp
  tests/stress/grazing_rays_test.cpp
  tests/stress/non_finite_input_test.cpp
  tests/stress/backend_parity_test.cpp
  tests/stress/fuzz_regression_test.cpp
  tests/stress/csg_stress_test.cpp)
