# Finds the OpenCV modules semfuse uses (core, imgproc, imgcodecs, dnn, features2d, calib3d) and defines the
# imported targets semfuse::opencv_<module>.
#
# Debian ships OpenCV's CMake package only in the libopencv-dev metapackage, which pulls in
# VTK, Qt and many unused modules. The narrow libopencv-{core,imgproc,imgcodecs,dnn,features2d,calib3d}-dev
# packages ship headers and libraries but no CMake config, so they are located here directly.
# A full OpenCV install with its own config is used when present.
include_guard(GLOBAL)
set(_semfuse_opencv_modules core imgproc imgcodecs dnn features2d calib3d)

find_package(OpenCV 4 QUIET CONFIG COMPONENTS ${_semfuse_opencv_modules})
if(OpenCV_FOUND)
  foreach(m IN LISTS _semfuse_opencv_modules)
    if(NOT TARGET semfuse::opencv_${m})
      add_library(semfuse::opencv_${m} INTERFACE IMPORTED)
      set_target_properties(semfuse::opencv_${m} PROPERTIES INTERFACE_LINK_LIBRARIES opencv_${m})
    endif()
  endforeach()
  set(SemfuseOpenCV_FOUND TRUE)
  return()
endif()

find_path(SemfuseOpenCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
set(_semfuse_opencv_vars SemfuseOpenCV_INCLUDE_DIR)
foreach(m IN LISTS _semfuse_opencv_modules)
  find_library(SemfuseOpenCV_${m}_LIBRARY NAMES opencv_${m})
  list(APPEND _semfuse_opencv_vars SemfuseOpenCV_${m}_LIBRARY)
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SemfuseOpenCV REQUIRED_VARS ${_semfuse_opencv_vars}
  REASON_FAILURE_MESSAGE "install libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-dnn-dev libopencv-features2d-dev libopencv-calib3d-dev (deploy/install-deps.sh)")

if(SemfuseOpenCV_FOUND)
  foreach(m IN LISTS _semfuse_opencv_modules)
    if(NOT TARGET semfuse::opencv_${m})
      add_library(semfuse::opencv_${m} UNKNOWN IMPORTED)
      set_target_properties(semfuse::opencv_${m} PROPERTIES
        IMPORTED_LOCATION "${SemfuseOpenCV_${m}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${SemfuseOpenCV_INCLUDE_DIR}")
    endif()
  endforeach()
endif()
