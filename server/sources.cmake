# The sources of the server's libraries that the fuzz targets reach, listed
# once, relative to server/: the libraries here (CMakeLists.txt) and the fuzz
# build (tests/fuzz, which compiles them again, instrumented) both take them
# from these lists, as algorithms/sources.cmake does for the algorithms.
set(CGVIEW_UPLOAD_SOURCES upload_read.cpp child_process.cpp sandbox.cpp jobs/job_files.cpp)
set(CGVIEW_STORE_SOURCES store.cpp auth.cpp tickets.cpp rate_limit.cpp mesh_service.cpp quota.cpp)
# The executors, whose registry the settings name (config.cpp).
set(CGVIEW_EXECUTOR_SOURCES jobs/executor.cpp jobs/executor_registry.cpp jobs/worker_result.cpp jobs/local_executor.cpp
  jobs/slurm_executor.cpp)
set(CGVIEW_TEACHING_SOURCES teaching/courses.cpp teaching/grading.cpp teaching/rooms.cpp)
set(CGVIEW_CONFIG_SOURCES config.cpp)
