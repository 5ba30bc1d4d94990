list(APPEND LRAY_CORE_SOURCES src/run/options.cpp src/run/output_options.cpp
     src/run/sampling_options.cpp src/run/limit_options.cpp src/run/farm_options.cpp
     src/run/preview_options.cpp src/run/run_plan.cpp src/run/render_stats.cpp
     src/run/frame_pipeline.cpp src/run/render_threads.cpp src/run/scene_motion.cpp)
