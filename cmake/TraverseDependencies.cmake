# Every external dependency is found here, once. The Debian package names live in
# .ci/debian-packages.txt.

find_package(MPI REQUIRED COMPONENTS C CXX)
# traverse calls MPI's C interface only: without the deprecated C++ bindings (which mpi.h
# pulls into every C++ file otherwise) the executables need no libmpi_cxx.
add_compile_definitions(OMPI_SKIP_MPICXX=1 MPICH_SKIP_MPICXX=1)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

# Trilinos: ask only for the components used (a bare find_package fails on Debian because
# some package configs name packages that are not installed).
find_package(Trilinos REQUIRED COMPONENTS
  Teuchos Kokkos Tpetra Thyra Stratimikos Belos Ifpack2 Amesos2 NOX Anasazi)
# Imported Trilinos targets carry link dependencies but no include directories.
add_library(traverse_teuchos INTERFACE)
target_include_directories(traverse_teuchos SYSTEM INTERFACE ${Trilinos_INCLUDE_DIRS} ${Trilinos_TPL_INCLUDE_DIRS})
target_link_libraries(traverse_teuchos INTERFACE trilinos_teuchoscore trilinos_teuchosparameterlist trilinos_teuchoscomm trilinos_teuchosparser MPI::MPI_CXX)
add_library(traverse_trilinos INTERFACE)
target_include_directories(traverse_trilinos SYSTEM INTERFACE ${Trilinos_INCLUDE_DIRS} ${Trilinos_TPL_INCLUDE_DIRS})
target_link_libraries(traverse_trilinos INTERFACE ${Trilinos_LIBRARIES} ${Trilinos_TPL_LIBRARIES} MPI::MPI_CXX)

# METIS 5 ships neither a CMake nor a pkg-config file.
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(traverse_metis INTERFACE)
target_include_directories(traverse_metis SYSTEM INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(traverse_metis INTERFACE ${METIS_LIBRARY})

# Parallel HDF5 (MPI-IO) C API.
set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "traverse needs a parallel (MPI-IO) HDF5; on Debian install libhdf5-openmpi-dev")
endif()
add_library(traverse_hdf5 INTERFACE)
target_include_directories(traverse_hdf5 SYSTEM INTERFACE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
target_link_libraries(traverse_hdf5 INTERFACE ${HDF5_C_LIBRARIES} MPI::MPI_C)
target_compile_definitions(traverse_hdf5 INTERFACE ${HDF5_C_DEFINITIONS})

# The same HDF5 as a static archive, for the executable traverse only (docs/developer.md,
# "Start-up"): Debian's shared libhdf5 loads libcurl and its TLS, Kerberos and LDAP chain
# (about 30 libraries, two thirds of an empty program's start here) for a remote-file
# driver traverse never uses; linked statically only the objects traverse calls come in.
# Falls back to the shared library when the archive is absent or does not link.
set(TRAVERSE_HDF5_LEAN traverse_hdf5)
set(_traverse_h5_archive "")
foreach(_lib IN LISTS HDF5_C_LIBRARIES)
  if(_lib MATCHES "libhdf5[^/]*\\.so$" AND NOT _lib MATCHES "_hl")
    string(REGEX REPLACE "\\.so$" ".a" _a "${_lib}")
    if(EXISTS "${_a}")
      set(_traverse_h5_archive "${_a}")
    endif()
  endif()
endforeach()
if(_traverse_h5_archive)
  find_library(TRAVERSE_SZ_LIBRARY sz)
  find_library(TRAVERSE_Z_LIBRARY z)
  set(_h5_static_libs ${_traverse_h5_archive} ${TRAVERSE_SZ_LIBRARY} ${TRAVERSE_Z_LIBRARY} ${CMAKE_DL_LIBS} m)
  include(CheckCSourceCompiles)
  set(CMAKE_REQUIRED_INCLUDES ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS} ${MPI_C_INCLUDE_DIRS})
  set(CMAKE_REQUIRED_LIBRARIES ${_h5_static_libs} ${MPI_C_LIBRARIES})
  set(CMAKE_REQUIRED_QUIET TRUE)
  check_c_source_compiles([=[
#include <hdf5.h>
int main(void) {
  hid_t fa = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fa, MPI_COMM_WORLD, MPI_INFO_NULL);
  hid_t dc = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_deflate(dc, 1);
  hid_t f = H5Fcreate("x.h5", H5F_ACC_TRUNC, H5P_DEFAULT, fa);
  return (int)H5Fclose(f);
}]=] TRAVERSE_HDF5_STATIC_LINKS)
  unset(CMAKE_REQUIRED_INCLUDES)
  unset(CMAKE_REQUIRED_LIBRARIES)
  unset(CMAKE_REQUIRED_QUIET)
  if(TRAVERSE_HDF5_STATIC_LINKS)
    add_library(traverse_hdf5_static INTERFACE)
    target_include_directories(traverse_hdf5_static SYSTEM INTERFACE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
    target_link_libraries(traverse_hdf5_static INTERFACE ${_h5_static_libs} MPI::MPI_C)
    target_compile_definitions(traverse_hdf5_static INTERFACE ${HDF5_C_DEFINITIONS})
    set(TRAVERSE_HDF5_LEAN traverse_hdf5_static)
  endif()
endif()
message(STATUS "HDF5 of the executable traverse: ${TRAVERSE_HDF5_LEAN} ${_traverse_h5_archive}")

# Python for postprocessing: an interpreter that imports numpy, h5py and matplotlib.
set(_traverse_py_candidates /usr/bin/python3)
find_program(_traverse_path_python python3)
if(_traverse_path_python)
  list(APPEND _traverse_py_candidates ${_traverse_path_python})
endif()
unset(TRAVERSE_PYTHON)
foreach(_py IN LISTS _traverse_py_candidates)
  if(NOT TRAVERSE_PYTHON AND EXISTS ${_py})
    execute_process(COMMAND ${_py} -c "import numpy, h5py, matplotlib"
                    RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
    if(_rc EQUAL 0)
      set(TRAVERSE_PYTHON ${_py})
    endif()
  endif()
endforeach()
if(NOT TRAVERSE_PYTHON)
  message(WARNING "No python3 that imports numpy, h5py and matplotlib: the tests that need it are registered as failing stand-ins")
else()
  message(STATUS "Postprocessing interpreter: ${TRAVERSE_PYTHON}")
endif()

find_package(GTest)
