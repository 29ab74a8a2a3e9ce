# Every external dependency is found here, once. The Debian package names live in
# .ci/debian-packages.txt.

find_package(MPI REQUIRED COMPONENTS C CXX)
# traverse calls MPI's C interface only: no deprecated C++ bindings.
add_compile_definitions(OMPI_SKIP_MPICXX=1 MPICH_SKIP_MPICXX=1)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

# Trilinos: ask only for the components used (a bare find_package fails on Debian because
# some package configs name packages that are not installed).
find_package(Trilinos REQUIRED COMPONENTS
  Teuchos Kokkos Tpetra Thyra Stratimikos Belos Ifpack2 Amesos2 NOX Anasazi)
# Imported Trilinos targets carry link dependencies but no include directories.
add_library(traverse_trilinos INTERFACE)
target_include_directories(traverse_trilinos SYSTEM INTERFACE ${Trilinos_INCLUDE_DIRS} ${Trilinos_TPL_INCLUDE_DIRS})
target_link_libraries(traverse_trilinos INTERFACE ${Trilinos_LIBRARIES} ${Trilinos_TPL_LIBRARIES} MPI::MPI_CXX)
# Teuchos' parameter lists alone (the scene's tree), without the solver packages.
add_library(traverse_teuchos INTERFACE)
target_include_directories(traverse_teuchos SYSTEM INTERFACE ${Trilinos_INCLUDE_DIRS})
target_link_libraries(traverse_teuchos INTERFACE ${TeuchosParameterList_LIBRARIES})

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
