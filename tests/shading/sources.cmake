list(APPEND LRAY_TEST_SOURCES tests/shading/pigments/perlin_noise_test.cpp tests/shading/pigments/texture_map_test.cpp
     tests/shading/pigment_test.cpp tests/shading/image_cache_test.cpp
     tests/shading/integrator_test.cpp tests/shading/shadow_batch_test.cpp
     tests/shading/brute_force_render.cpp
     tests/shading/spot_light_test.cpp tests/shading/shadow_shaft_test.cpp
     tests/shading/exr_header_test.cpp src/shading/exr_header.cpp
     tests/shading/path_integrator_test.cpp tests/shading/ggx_test.cpp
     tests/shading/rough_lobes_test.cpp tests/shading/emitters_test.cpp
     tests/shading/light_lanes_test.cpp)
