list(APPEND LRAY_CORE_SOURCES src/app/options.cpp src/app/progress_bar.cpp src/app/render_stats.cpp
                              src/app/frame_pipeline.cpp src/app/app.cpp src/app/merge.cpp)
