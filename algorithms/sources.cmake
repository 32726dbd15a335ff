# The sources of the libraries that the fuzz targets reach, listed once,
# relative to algorithms/: the libraries here (CMakeLists.txt) and the fuzz
# build (tests/fuzz, a project of its own that compiles them again,
# instrumented) both take them from these lists.
set(CGVIEW_CORE_SOURCES
  core/errors.cpp core/mesh.cpp core/point_cloud.cpp core/mesh_report.cpp core/orient.cpp core/scalar_field.cpp core/vector_field.cpp
  core/voxel_grid.cpp core/skeleton.cpp core/animation.cpp core/cluster_decimate.cpp core/shared_library.cpp)
set(CGVIEW_IO_SOURCES
  io/mesh_io.cpp io/mesh_formats.cpp io/read_off.cpp io/read_obj.cpp io/read_ply.cpp io/read_stl.cpp io/read_xyz.cpp
  io/write_text.cpp io/draco_io.cpp io/gltf_io.cpp io/samples.cpp io/skeleton_io.cpp io/materials.cpp
  io/parse_json.cpp)
set(CGVIEW_ZIP_SOURCES io/zip_bundle.cpp)
set(CGVIEW_REGISTRY_SOURCES registry/registry.cpp registry/artifact_io.cpp
  artifacts/artifact_codec.cpp artifacts/mesh_codec.cpp artifacts/scalar_field_codec.cpp artifacts/vector_field_codec.cpp
  artifacts/voxel_grid_codec.cpp artifacts/skeleton_codec.cpp artifacts/metrics_codec.cpp
  artifacts/text_codec.cpp artifacts/animation_codec.cpp artifacts/points_codec.cpp)
# The voxel file formats, one file each (cgview_voxel).
set(CGVIEW_VOXEL_FORMAT_SOURCES voxel/voxel_file_parts.cpp voxel/binvox.cpp voxel/nrrd.cpp voxel/vti.cpp voxel/vox.cpp
  voxel/raw_voxels.cpp)
# Voxel grid operations and the loader of OpenVDB's module (cgview_voxel), and the module itself (cgview_vdb).
set(CGVIEW_VOXEL_SOURCES voxel/voxel_ops.cpp voxel/voxel_io.cpp voxel/voxel_vdb_load.cpp)
set(CGVIEW_VDB_SOURCES voxel/voxel_vdb.cpp)
# The EGL context alone: the config file names its platforms (the server's settings).
set(CGVIEW_EGL_SOURCES render/egl_context.cpp)
