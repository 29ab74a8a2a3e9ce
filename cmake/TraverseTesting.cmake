# traverse_add_gtest(<name> SOURCES <files...> LIBS <targets...> [RANKS <n>...] [LABELS <l>...]
#                    [TIMEOUT <s>] [MPI_MAIN] [ONE_RANK <gtest filter>] [ARGS <a>...])
# Builds one GoogleTest executable and registers it with ctest. With RANKS, one ctest entry
# per rank count is added, run through mpiexec (as root too, oversubscribing if needed).
# Every entry is labelled with the name of its folder under tests/ (core, scene, mesh,
# output, beam, rod, solver, app, validation, stress, ...), plus "mpi" with RANKS, plus
# LABELS. MPI_MAIN links tests/support/mpi_main.cpp (MPI and Kokkos set up around
# GoogleTest); GTest::gtest_main in LIBS is replaced by tests/support/gtest_main.cpp. Both
# exit with 77 when a case called GTEST_SKIP and none failed, and ctest shows that entry
# as skipped (SKIP_RETURN_CODE), never as passed. ONE_RANK: the cases (a gtest filter, e.g.
# "Suite.CaseA:Suite.CaseB") that are about one process; they run in the 1-rank entry only.
# ARGS: arguments of the entry without RANKS (e.g. a gtest filter). tests/support
# (process.hpp: the one helper for tests that run the executable; reference_stepper.hpp and
# reference_statics.hpp: the rod's independent references, linked into every test) is on every
# test's include path.
function(traverse_add_gtest name)
  cmake_parse_arguments(T "MPI_MAIN" "TIMEOUT;ONE_RANK" "SOURCES;LIBS;RANKS;LABELS;ARGS" ${ARGN})
  get_filename_component(folder ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  list(PREPEND T_LABELS ${folder})
  if(T_MPI_MAIN)
    list(APPEND T_SOURCES ${PROJECT_SOURCE_DIR}/tests/support/mpi_main.cpp)
  elseif(GTest::gtest_main IN_LIST T_LIBS)
    list(REMOVE_ITEM T_LIBS GTest::gtest_main)
    list(APPEND T_SOURCES ${PROJECT_SOURCE_DIR}/tests/support/gtest_main.cpp)
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
    add_test(NAME ${name} COMMAND ${name} ${T_ARGS})
    set_tests_properties(${name} PROPERTIES TIMEOUT ${T_TIMEOUT} LABELS "${T_LABELS}" SKIP_RETURN_CODE 77)
  else()
    foreach(n IN LISTS T_RANKS)
      set(filter "")
      if(T_ONE_RANK AND n GREATER 1)
        set(filter "--gtest_filter=-${T_ONE_RANK}")
      endif()
      add_test(NAME ${name}_np${n}
               COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${n} --oversubscribe
                       ${MPIEXEC_PREFLAGS} $<TARGET_FILE:${name}> ${MPIEXEC_POSTFLAGS} ${filter})
      set_tests_properties(${name}_np${n} PROPERTIES TIMEOUT ${T_TIMEOUT} PROCESSORS ${n} SKIP_RETURN_CODE 77
        LABELS "mpi;${T_LABELS}"
        ENVIRONMENT "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
    endforeach()
  endif()
endfunction()

# traverse_add_python_stand_ins(LABELS <labels> NAMES <test names...>)
# Without the python of the figure scripts (TRAVERSE_PYTHON), the tests that need it are
# registered as stand-ins that fail and say what is missing: a configuration without it shows
# them as failed, never drops them.
function(traverse_add_python_stand_ins)
  cmake_parse_arguments(T "" "" "LABELS;NAMES" ${ARGN})
  foreach(name IN LISTS T_NAMES)
    add_test(NAME ${name}
             COMMAND ${CMAKE_COMMAND} "-DMSG=${name}: no python3 that imports numpy, h5py and matplotlib (Debian: python3-numpy python3-h5py python3-matplotlib)"
                     -P ${PROJECT_SOURCE_DIR}/tests/output/missing_client.cmake)
    set_tests_properties(${name} PROPERTIES LABELS "${T_LABELS}")
  endforeach()
endfunction()
