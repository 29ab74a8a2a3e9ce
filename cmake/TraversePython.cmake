# The Python module traverse (src/python, docs/python.md): pybind11 from Debian's pybind11-dev
# and the interpreter /usr/bin/python3 (Python3_EXECUTABLE overrides it) with its headers.
# TRAVERSE_PYTHON_MODULE is ON when both are found; TRAVERSE_PYTHON_MISSING then says what is
# missing (tests/python registers failing stand-ins that say it).
set(TRAVERSE_PYTHON_MODULE OFF)
set(TRAVERSE_PYTHON_MISSING "")
if(TRAVERSE_BUILD_PYTHON)
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 COMPONENTS Interpreter Development)
  if(Python3_FOUND)
    find_package(pybind11 CONFIG)
  endif()
  if(NOT Python3_FOUND)
    set(TRAVERSE_PYTHON_MISSING "no python3 with its development headers (Debian: python3-dev)")
  elseif(NOT pybind11_FOUND)
    set(TRAVERSE_PYTHON_MISSING "no pybind11 (Debian: pybind11-dev python3-pybind11)")
  else()
    set(TRAVERSE_PYTHON_MODULE ON)
    # Where `cmake --install` puts the package: the interpreter's own site-packages for local
    # installs (what sysconfig reports; on Debian /usr/local/lib/python3.X/dist-packages, on
    # its search path), relative to the install prefix when under it (so --prefix moves it).
    if(NOT DEFINED TRAVERSE_PYTHON_INSTALL_DIR)
      execute_process(COMMAND ${Python3_EXECUTABLE} -c "import sysconfig; print(sysconfig.get_path('platlib'))"
                      OUTPUT_VARIABLE _traverse_platlib OUTPUT_STRIP_TRAILING_WHITESPACE)
      string(FIND "${_traverse_platlib}" "${CMAKE_INSTALL_PREFIX}/" _at)
      if(_at EQUAL 0)
        file(RELATIVE_PATH _traverse_platlib "${CMAKE_INSTALL_PREFIX}" "${_traverse_platlib}")
      endif()
      set(TRAVERSE_PYTHON_INSTALL_DIR "${_traverse_platlib}" CACHE STRING
          "Where cmake --install puts the Python package traverse (relative: under the install prefix)")
    endif()
    message(STATUS "Python module traverse: ${Python3_EXECUTABLE} ${Python3_VERSION}, pybind11 ${pybind11_VERSION}; installs into ${TRAVERSE_PYTHON_INSTALL_DIR}")
  endif()
  if(TRAVERSE_PYTHON_MISSING)
    message(WARNING "The Python module traverse is not built: ${TRAVERSE_PYTHON_MISSING}")
  endif()
endif()
