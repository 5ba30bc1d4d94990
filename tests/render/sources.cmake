list(APPEND LRAY_TEST_SOURCES tests/render/image_writer_test.cpp tests/render/srgb_bytes_test.cpp
     tests/render/camera_rays_test.cpp
     tests/render/adaptive_sampling_test.cpp tests/render/motion_blur_test.cpp
     tests/render/film_test.cpp tests/render/owen_sobol_lanes_test.cpp
     tests/render/edge_lattice_test.cpp tests/render/sparse_centres_test.cpp)
