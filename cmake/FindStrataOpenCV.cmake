# Finds the three OpenCV modules Strata uses (core, imgproc, imgcodecs) from Debian's per-module -dev
# packages. Debian ships OpenCVConfig.cmake and opencv4.pc only in libopencv-dev, which pulls in about 140
# further packages (dnn, viz, VTK, ...) that Strata never links; this module avoids that install.
# Defines imported targets OpenCV::core, OpenCV::imgproc, OpenCV::imgcodecs.
include(FindPackageHandleStandardArgs)

find_path(StrataOpenCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
set(_strata_opencv_vars StrataOpenCV_INCLUDE_DIR)
foreach(module core imgproc imgcodecs)
  find_library(StrataOpenCV_${module}_LIBRARY NAMES opencv_${module})
  list(APPEND _strata_opencv_vars StrataOpenCV_${module}_LIBRARY)
endforeach()

if(StrataOpenCV_INCLUDE_DIR AND EXISTS "${StrataOpenCV_INCLUDE_DIR}/opencv2/core/version.hpp")
  file(STRINGS "${StrataOpenCV_INCLUDE_DIR}/opencv2/core/version.hpp" _v REGEX "#define CV_VERSION_(MAJOR|MINOR|REVISION) ")
  string(REGEX REPLACE ".*MAJOR ([0-9]+).*" "\\1" _major "${_v}")
  string(REGEX REPLACE ".*MINOR ([0-9]+).*" "\\1" _minor "${_v}")
  string(REGEX REPLACE ".*REVISION ([0-9]+).*" "\\1" _rev "${_v}")
  set(StrataOpenCV_VERSION "${_major}.${_minor}.${_rev}")
endif()

find_package_handle_standard_args(StrataOpenCV REQUIRED_VARS ${_strata_opencv_vars} VERSION_VAR StrataOpenCV_VERSION)

if(StrataOpenCV_FOUND)
  foreach(module core imgproc imgcodecs)
    if(NOT TARGET OpenCV::${module})
      add_library(OpenCV::${module} UNKNOWN IMPORTED)
      set_target_properties(OpenCV::${module} PROPERTIES
        IMPORTED_LOCATION "${StrataOpenCV_${module}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${StrataOpenCV_INCLUDE_DIR}")
    endif()
  endforeach()
  set_property(TARGET OpenCV::imgproc APPEND PROPERTY INTERFACE_LINK_LIBRARIES OpenCV::core)
  set_property(TARGET OpenCV::imgcodecs APPEND PROPERTY INTERFACE_LINK_LIBRARIES OpenCV::imgproc)
endif()
