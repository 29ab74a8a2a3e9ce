# ctest driver: run a scene with traverse, then draw its figure with a postprocessing script
# and check what the figure shows (check_figure.py: ink, extent, colours, a probe's values).
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
# The figure: drawn by the script and checked for what it shows (check_figure.py).
set(second_run "")
if(second)
  set(second_run ${second})
endif()
execute_process(COMMAND ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_figure.py ${SCRIPT} ${OUT}/run.png ${OUT}/run.h5
                        ${second_run} -- ${SCRIPT_ARGS} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SCRIPT}: the figure is wrong (${rc})")
endif()
foreach(f run.h5 run.xmf)
  file(SIZE ${OUT}/${f} size)
  if(size EQUAL 0)
    message(FATAL_ERROR "${f} is empty")
  endif()
endforeach()
