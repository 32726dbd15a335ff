# A minimal FindOpenVDB: the imported target OpenVDB::openvdb from Debian's
# libopenvdb-dev.  Debian's own FindOpenVDB.cmake asks for Boost.Iostreams'
# CMake package (not installed with libopenvdb-dev) and sets
# BUILD_SHARED_LIBS for the whole project, so CGView uses this one.
find_path(OpenVDB_INCLUDE_DIR openvdb/openvdb.h)
find_library(OpenVDB_LIBRARY openvdb)
find_library(OpenVDB_TBB_LIBRARY tbb)
# Its headers use Imath's half (imath_half_to_float_table).
find_library(OpenVDB_IMATH_LIBRARY Imath)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenVDB REQUIRED_VARS OpenVDB_LIBRARY OpenVDB_INCLUDE_DIR OpenVDB_TBB_LIBRARY OpenVDB_IMATH_LIBRARY)
if(OpenVDB_FOUND AND NOT TARGET OpenVDB::openvdb)
  add_library(OpenVDB::openvdb UNKNOWN IMPORTED)
  set_target_properties(OpenVDB::openvdb PROPERTIES
    IMPORTED_LOCATION "${OpenVDB_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenVDB_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${OpenVDB_TBB_LIBRARY};${OpenVDB_IMATH_LIBRARY}")
endif()
mark_as_advanced(OpenVDB_INCLUDE_DIR OpenVDB_LIBRARY OpenVDB_TBB_LIBRARY OpenVDB_IMATH_LIBRARY)
