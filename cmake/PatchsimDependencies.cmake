# Every dependency comes from a Debian 12 package (scripts/install-deps.sh installs them).

find_package(glm CONFIG REQUIRED)              # libglm-dev
find_package(nlohmann_json 3.10 CONFIG REQUIRED)  # nlohmann-json3-dev
find_package(CLI11 CONFIG REQUIRED)            # libcli11-dev
find_package(PkgConfig REQUIRED)

# OpenSubdiv (libosd-dev): Debian's CMake config names a static library that is not shipped,
# so find the headers and the shared osdCPU library directly.
find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/bfr/surface.h REQUIRED)
find_library(OPENSUBDIV_CPU_LIBRARY osdCPU REQUIRED)
add_library(patchsim::opensubdiv INTERFACE IMPORTED)
target_include_directories(patchsim::opensubdiv SYSTEM INTERFACE ${OPENSUBDIV_INCLUDE_DIR})
target_link_libraries(patchsim::opensubdiv INTERFACE ${OPENSUBDIV_CPU_LIBRARY})

# OpenImageIO (libopenimageio-dev): Debian's CMake target lists a missing /usr/include/opencv4
# include directory, so use its pkg-config file instead.
pkg_check_modules(OPENIMAGEIO REQUIRED IMPORTED_TARGET OpenImageIO)
add_library(patchsim::openimageio INTERFACE IMPORTED)
target_link_libraries(patchsim::openimageio INTERFACE PkgConfig::OPENIMAGEIO)

# Google Highway (libhwy-dev): the rasterizer's SIMD kernels, dispatched at run time to the host's
# best instruction set.
pkg_check_modules(HWY REQUIRED IMPORTED_TARGET libhwy)
add_library(patchsim::highway INTERFACE IMPORTED)
target_link_libraries(patchsim::highway INTERFACE PkgConfig::HWY)

if(PATCHSIM_BUILD_TESTS)
  find_package(GTest REQUIRED)                 # libgtest-dev, libgmock-dev
endif()
if(PATCHSIM_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)             # libbenchmark-dev
endif()

# glm's SYSTEM include keeps its headers out of our warnings.
set_target_properties(glm::glm PROPERTIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES
                      "$<TARGET_PROPERTY:glm::glm,INTERFACE_INCLUDE_DIRECTORIES>")
