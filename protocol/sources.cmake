# The protocol library's sources, relative to protocol/: its CMakeLists.txt
# and the fuzz build (tests/fuzz) take them from here.
set(CGVIEW_PROTOCOL_SOURCES mesh_report_json.cpp mesh_json.cpp job_json.cpp frames.cpp algorithm_json.cpp voxel_slice.cpp
  animation_frames.cpp stored_order.cpp)
