# Finds glint's Debian 12 dependencies, working around the packaging quirks recorded in
# ../shared/notes (OCIO's misplaced CMake config, OIIO's stray OpenCV include path).
find_package(embree 3 REQUIRED)
find_package(TBB REQUIRED)
find_package(OpenEXR REQUIRED)
find_package(OpenImageIO REQUIRED)
# PLY and OBJ import (scenes/mesh_import.cpp); Debian ships assimpConfig.cmake.
find_package(assimp REQUIRED)
find_package(draco REQUIRED)  # KHR_draco_mesh_compression (libdraco-dev)
find_package(meshoptimizer REQUIRED)  # EXT_meshopt_compression (libmeshoptimizer-dev)
find_package(nlohmann_json 3 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
# VDB media: OpenVDB (libopenvdb-dev) and NanoVDB (libnanovdb-dev, header-only). Debian's
# FindOpenVDB.cmake (in its own folder, beside its own FindTBB and FindOpenEXR) insists on
# Boost.Iostreams' CMake package, which only OpenVDB's build needs; the library and its
# headers are all glint uses, so the target is made here. Its headers include Boost's
# (libboost-dev, which libopenvdb-dev does not depend on) and Imath's.
find_path(OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
find_library(OPENVDB_LIBRARY openvdb REQUIRED)
find_path(BOOST_INCLUDE_DIR boost/any.hpp REQUIRED)
find_package(Imath REQUIRED)  # half floats, in OpenVDB's headers (libimath-dev)
add_library(OpenVDB::openvdb UNKNOWN IMPORTED)
set_target_properties(OpenVDB::openvdb PROPERTIES
  IMPORTED_LOCATION "${OPENVDB_LIBRARY}"
  INTERFACE_INCLUDE_DIRECTORIES "${OPENVDB_INCLUDE_DIR};${BOOST_INCLUDE_DIR}"
  INTERFACE_LINK_LIBRARIES "TBB::tbb;Imath::Imath")
find_path(NANOVDB_INCLUDE_DIR nanovdb/NanoVDB.h REQUIRED)
find_package(PkgConfig REQUIRED)

# Debian installs OpenColorIOConfig.cmake where find_package does not look, and with a hint it
# computes a wrong include path; pkg-config is reliable.
pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET OpenColorIO)

# Debian's OpenImageIO target lists /usr/include/opencv4 although OpenCV is not a dependency;
# CMake refuses to generate when that folder is missing. Drop the entry.
foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
  if(dirs)
    list(FILTER dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${dirs}")
  endif()
endforeach()

if(GLINT_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(GLINT_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# cpp-httplib (libcpp-httplib-dev): the local server of `glint preview`. Debian builds it as a
# shared library with a pkg-config file (its definitions select the same TLS and compression
# options the library was built with), no CMake package.
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
find_package(Threads REQUIRED)
