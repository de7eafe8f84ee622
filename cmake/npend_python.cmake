# Whether to build the Python module (NPEND_BUILD_PYTHON), and with which Python.
#
# Debian's /usr/bin/python3 is the interpreter tools/setup.sh installs numpy, pytest and
# pybind11 for; another python3 earlier on PATH (pyenv, a virtualenv) would lack them. Give
# -DPython_EXECUTABLE=... to build for another one.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3)
endif()

set(npend_with_python ${NPEND_BUILD_PYTHON})
if(NPEND_BUILD_PYTHON STREQUAL "AUTO")
  set(npend_with_python OFF)
  if(NOT NPEND_SANITIZE AND NOT NPEND_BUILD_FUZZERS)
    find_package(Python 3 QUIET COMPONENTS Interpreter Development.Module)
    find_package(pybind11 CONFIG QUIET)
    if(Python_FOUND AND pybind11_FOUND)
      set(npend_with_python ON)
    else()
      message(STATUS "npend: pybind11 or Python's headers not found, the Python module is not built")
    endif()
  endif()
endif()
if(npend_with_python)
  # Not EXCLUDE_FROM_ALL on the folder, which would drop its install rules too: the module
  # itself is kept out of `all` (python/CMakeLists.txt).
  add_subdirectory(python)
endif()
