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
