# Progress on stderr when it is not a terminal (--progress): every report is its own line
# (no carriage returns), with the steps per second and the time left. A report at every step
# (output.progress_interval = 0), so the lines do not depend on how long the run takes.
# Variables: EXE, SCENE, OUT (an output file).
execute_process(COMMAND ${EXE} run ${SCENE} -o ${OUT} --overwrite --progress
                        --set time.dt=1e-4 --set output.every=100 --set output.progress_interval=0
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
set(failed 0)
if(NOT rc EQUAL 0)
  message("FAILED: the run exits with ${rc}: ${err}")
  math(EXPR failed "${failed} + 1")
endif()
string(FIND "${err}" "\r" cr)
if(NOT cr EQUAL -1)
  message("FAILED: a carriage return in the progress written to a file")
  math(EXPR failed "${failed} + 1")
endif()
string(REGEX MATCHALL "  t = [^\n]* steps/s, about [0-9]+ s left\n" lines "${err}")
list(LENGTH lines n)
if(n LESS 1)
  message("FAILED: no complete progress line in '${err}'")
  math(EXPR failed "${failed} + 1")
endif()
math(EXPR passed "3 - ${failed}")
message("${n} progress lines; ${passed} passed, ${failed} failed")
if(failed GREATER 0)
  message(FATAL_ERROR "progress lines are wrong")
endif()
