# traverse_add_gtest(<name> SOURCES <files...> LIBS <targets...> [RANKS <n>...] [LABELS <l>...]
#                    [TIMEOUT <s>])
# Builds one GoogleTest executable and registers it with ctest. With RANKS, one ctest entry
# per rank count is added, run through mpiexec (as root too, oversubscribing if needed).
function(traverse_add_gtest name)
  cmake_parse_arguments(T "" "TIMEOUT" "SOURCES;LIBS;RANKS;LABELS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest traverse_warnings)
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
