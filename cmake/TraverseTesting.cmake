# traverse_add_gtest(<name> SOURCES <files...> LIBS <targets...> [RANKS <n>...] [LABELS <l>...]
#                    [TIMEOUT <s>] [MPI_MAIN])
# Builds one GoogleTest executable and registers it with ctest. With RANKS, one ctest entry
# per rank count is added, run through mpiexec (as root too, oversubscribing if needed).
# Every entry is labelled with the name of its folder under tests/ (core, scene, mesh,
# output, beam, rod, solver, app, validation, stress, ...), plus "mpi" with RANKS, plus
# LABELS. MPI_MAIN links tests/support/mpi_main.cpp (MPI and Kokkos set up around
# GoogleTest) instead of GTest::gtest_main. tests/support (process.hpp: the one helper for
# tests that run the executable; reference_stepper.hpp: the rod step's independent reference,
# linked into every test) is on every test's include path.
function(traverse_add_gtest name)
  cmake_parse_arguments(T "MPI_MAIN" "TIMEOUT" "SOURCES;LIBS;RANKS;LABELS" ${ARGN})
  get_filename_component(folder ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  list(PREPEND T_LABELS ${folder})
  if(T_MPI_MAIN)
    list(APPEND T_SOURCES ${PROJECT_SOURCE_DIR}/tests/support/mpi_main.cpp)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
  target_link_libraries(${name} PRIVATE ${T_LIBS} traverse_reference_stepper GTest::gtest traverse_warnings)
  target_compile_definitions(${name} PRIVATE
    TRAVERSE_SOURCE_DIR="${PROJECT_SOURCE_DIR}" TRAVERSE_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 600)
  endif()
  if(TRAVERSE_SANITIZE)  # leak checking with full malloc stacks: up to 10x slower (docs/reliability.md)
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * 3")
  endif()
  if(NOT T_RANKS)
    add_test(NAME ${name} COMMAND ${name})
    set_tests_properties(${name} PROPERTIES TIMEOUT ${T_TIMEOUT} LABELS "${T_LABELS}")
  else()
    foreach(n IN LISTS T_RANKS)
      add_test(NAME ${name}_np${n}
               COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${n} --oversubscribe
                       ${MPIEXEC_PREFLAGS} $<TARGET_FILE:${name}> ${MPIEXEC_POSTFLAGS})
      set_tests_properties(${name}_np${n} PROPERTIES TIMEOUT ${T_TIMEOUT} PROCESSORS ${n}
        LABELS "mpi;${T_LABELS}"
        ENVIRONMENT "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
    endforeach()
  endif()
endfunction()
