# All third-party dependencies, from Debian 12 packages (scripts/setup.sh).
find_package(Threads REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres 2.0 REQUIRED)
find_package(apriltag REQUIRED)
find_package(glm REQUIRED)
find_package(CLI11 REQUIRED)

# Debian's per-module OpenCV packages ship no OpenCVConfig.cmake (that comes
# with libopencv-dev, which drags in VTK, a JDK and GDAL), so we make imported
# targets opencv::<module> ourselves.
find_path(RIPPLE_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
foreach(module core imgproc calib3d imgcodecs videoio highgui)
  find_library(RIPPLE_OPENCV_${module}_LIBRARY opencv_${module} REQUIRED)
  add_library(opencv::${module} SHARED IMPORTED)
  set_target_properties(opencv::${module} PROPERTIES
    IMPORTED_LOCATION "${RIPPLE_OPENCV_${module}_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${RIPPLE_OPENCV_INCLUDE_DIR}")
endforeach()

# libapriltag-utils exports helpers (image_u8_destroy, ...) that apriltag.h
# declares; see DESIGN.md.
if(NOT TARGET apriltag::apriltag-utils)
  message(FATAL_ERROR "apriltag::apriltag-utils target missing")
endif()

# GL backends (render/).
find_package(OpenGL REQUIRED COMPONENTS OpenGL)
if(RIPPLE_WITH_EGL)
  find_package(OpenGL COMPONENTS EGL)
  if(NOT OpenGL_EGL_FOUND)
    message(WARNING "EGL not found: RIPPLE_WITH_EGL disabled")
    set(RIPPLE_WITH_EGL OFF)
  endif()
endif()
if(RIPPLE_WITH_OSMESA)
  find_path(RIPPLE_OSMESA_INCLUDE_DIR GL/osmesa.h)
  find_library(RIPPLE_OSMESA_LIBRARY OSMesa)
  if(NOT RIPPLE_OSMESA_INCLUDE_DIR OR NOT RIPPLE_OSMESA_LIBRARY)
    message(WARNING "OSMesa not found: RIPPLE_WITH_OSMESA disabled")
    set(RIPPLE_WITH_OSMESA OFF)
  endif()
endif()
if(RIPPLE_WITH_GLFW)
  find_package(glfw3 3.3)
  if(NOT glfw3_FOUND)
    message(WARNING "GLFW not found: RIPPLE_WITH_GLFW disabled")
    set(RIPPLE_WITH_GLFW OFF)
  endif()
endif()

find_package(PkgConfig REQUIRED)
pkg_check_modules(CAIRO IMPORTED_TARGET cairo)
# FFTW (single precision) for the water's cosine transforms (sim/).
pkg_check_modules(FFTW3F REQUIRED IMPORTED_TARGET fftw3f)
# libyaml's event parser reads the rig and camera files (tracking/yaml_tree.h;
# README, "Untrusted files").
pkg_check_modules(YAML REQUIRED IMPORTED_TARGET yaml-0.1)
# libavutil: FFmpeg's log lines are routed through our own callback
# (app/app_third_party_log.h).
pkg_check_modules(AVUTIL REQUIRED IMPORTED_TARGET libavutil)

if(RIPPLE_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(RIPPLE_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
