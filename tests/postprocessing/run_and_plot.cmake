# ctest driver: run a scene with traverse, then draw its figure with a postprocessing script,
# and check that the HDF5 output and the PNG exist and are not empty.
# Variables: EXE, PYTHON, SCENE, SCRIPT, OUT (folder), ARGS (extra traverse arguments, ;-list);
# optional SCENE2 (run with the same ARGS, its output the script's second argument) and
# SCRIPT_ARGS (extra script arguments, ;-list).
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${EXE} run ${SCENE} -o ${OUT}/run.h5 -q ${ARGS} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "traverse run failed (${rc})")
endif()
set(second "")
if(SCENE2)  # a second run (the same ARGS) for a script that compares two runs
  execute_process(COMMAND ${EXE} run ${SCENE2} -o ${OUT}/run2.h5 -q ${ARGS} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "traverse run of ${SCENE2} failed (${rc})")
  endif()
  set(second ${OUT}/run2.h5)
endif()
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${OUT}/run.h5 ${second} ${SCRIPT_ARGS} -o ${OUT}/run.png RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SCRIPT} failed (${rc})")
endif()
foreach(f run.h5 run.xmf run.png)
  file(SIZE ${OUT}/${f} size)
  if(size EQUAL 0)
    message(FATAL_ERROR "${f} is empty")
  endif()
endforeach()
message(STATUS "1 passed, 0 failed")
