list(APPEND LRAY_CORE_SOURCES src/render/image_writer.cpp src/render/renderer.cpp
     src/render/backends.cpp src/render/output_file.cpp src/render/sample_buffer.cpp
     src/render/tile_file.cpp src/render/owen_sobol_lanes.cpp
     src/render/srgb_bytes.cpp)
