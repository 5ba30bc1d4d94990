list(APPEND LRAY_CORE_SOURCES src/shading/pigments/perlin_noise.cpp src/shading/pigments/texture_map.cpp
     src/shading/pigments/texture_image.cpp src/shading/image_cache.cpp src/shading/texture_file.cpp src/shading/shadow_shaft.cpp src/shading/light_lanes.cpp src/shading/oiio_library.cpp src/shading/pigment.cpp
     src/shading/emitters.cpp
     src/shading/pigments/checker_pigment_2d.cpp src/shading/pigments/checker_pigment_3d.cpp
     src/shading/pigments/marble_pigment_3d.cpp src/shading/pigments/wood_pigment_3d.cpp
     src/shading/pigments/image_pigment_2d.cpp
     src/shading/material_table.cpp src/shading/shadow_batch.cpp)
