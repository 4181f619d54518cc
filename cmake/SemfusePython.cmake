# The Python bindings' toolchain: pybind11 (Debian pybind11-dev) and a Python 3 interpreter with its
# headers that imports numpy (Debian python3-dev, python3-numpy). The interpreter is the one in
# PATH when it imports numpy, else /usr/bin/python3: a pyenv or venv interpreter first in PATH often
# lacks numpy. -DPython3_EXECUTABLE=... chooses another. Sets SEMFUSE_PYTHON_FOUND, the default of
# SEMFUSE_BUILD_PYTHON, and SEMFUSE_PYTHON_INSTALL_DIR (site packages, relative to the prefix).
include_guard(GLOBAL)

set(SEMFUSE_PYTHON_FOUND OFF)
if(NOT DEFINED Python3_EXECUTABLE)
  find_program(SEMFUSE_PYTHON3_IN_PATH NAMES python3)
  foreach(candidate IN ITEMS "${SEMFUSE_PYTHON3_IN_PATH}" /usr/bin/python3)
    if(candidate AND EXISTS "${candidate}")
      execute_process(COMMAND "${candidate}" -c "import numpy" RESULT_VARIABLE numpy_missing OUTPUT_QUIET ERROR_QUIET)
      if(numpy_missing EQUAL 0)
        set(Python3_EXECUTABLE "${candidate}" CACHE FILEPATH "The Python the semfuse package is built for (one with numpy)")
        break()
      endif()
    endif()
  endforeach()
endif()

if(DEFINED Python3_EXECUTABLE)
  find_package(Python3 3.8 COMPONENTS Interpreter Development.Module QUIET)
  if(Python3_FOUND)
    set(PYBIND11_FINDPYTHON ON)
    find_package(pybind11 2.6 CONFIG QUIET)
    if(pybind11_FOUND)
      set(SEMFUSE_PYTHON_FOUND ON)
    endif()
  endif()
endif()

if(SEMFUSE_PYTHON_FOUND)
  # Debian's interpreters read /usr/local/lib/python3.X/dist-packages and /usr/lib/python3.X/dist-packages;
  # others read lib/python3.X/site-packages under their prefix.
  execute_process(COMMAND "${Python3_EXECUTABLE}" -c
                          "import sys; print('dist-packages' if any(p.endswith('dist-packages') for p in sys.path) else 'site-packages')"
                  OUTPUT_VARIABLE semfuse_site_folder OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(SEMFUSE_PYTHON_INSTALL_DIR "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/${semfuse_site_folder}"
      CACHE STRING "Where cmake --install puts the semfuse Python package, relative to the prefix")
endif()
