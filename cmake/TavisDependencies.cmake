# Third-party dependencies, all from Debian bookworm packages (.ci/install-deps installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(embree 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Threads REQUIRED)
find_package(PNG 1.6 REQUIRED)  # libpng-dev: the PNG files of renders, frames and figures
find_package(ZLIB REQUIRED)  # zlib1g-dev (libpng's own dependency): a cell's saved actions, gzip-compressed

find_package(PkgConfig REQUIRED)
pkg_check_modules(ODE REQUIRED IMPORTED_TARGET ode)
# FFmpeg 5.1 (libavcodec59 with libx264 and libsvtav1): the mp4 camera streams of datasets.
pkg_check_modules(FFMPEG REQUIRED IMPORTED_TARGET libavcodec libavformat libavutil libswscale)

# OpenCV: only core and imgproc are installed (libopencv-dev would pull in the whole GUI stack),
# and those packages ship no CMake config, so the imported target is built here. Not imgcodecs:
# its image formats load about 120 more shared libraries (GDAL, Poppler, HDF5...), which took
# 0.13 s at every start of `tavis`; PNG files are written and read through libpng instead.
find_path(OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
set(_tavis_opencv_libs)
foreach(_component core imgproc)
  find_library(OPENCV_${_component}_LIBRARY NAMES opencv_${_component} REQUIRED)
  list(APPEND _tavis_opencv_libs ${OPENCV_${_component}_LIBRARY})
endforeach()
add_library(tavis_opencv INTERFACE)
target_include_directories(tavis_opencv SYSTEM INTERFACE ${OPENCV_INCLUDE_DIR})
target_link_libraries(tavis_opencv INTERFACE ${_tavis_opencv_libs})

if(TAVIS_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(TAVIS_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# Parquet page codecs: Snappy (libsnappy-dev) to write and read, Zstandard (libzstd-dev) to read
# files others compressed with it. Both ship pkg-config files but no CMake config.
pkg_check_modules(SNAPPY REQUIRED IMPORTED_TARGET snappy)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
