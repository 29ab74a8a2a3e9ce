# ctest fixture of the real-client tests: a rod run and a beam run of the traverse program,
# small but with every kind of array (the rod's centreline r, directors R -> d1 d2 d3,
# curvature, stretch; the beam's default output), in OUT (a folder, recreated). The rod is
# extensible and soft (E A = 200 N, strains of about 1 %), so the clients see a stretched rod.
# Variables: EXE, SOURCE (the source tree), OUT.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${EXE} run ${SOURCE}/inputs/default.yaml -o ${OUT}/rod.h5 -q
                        --set mesh.ds=0.05 --set rod.model=extensible --set rod.axial_stiffness=200
                        --set "output.fields=[r,R,kappa,stretch]" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "traverse run (rod) failed (${rc})")
endif()
execute_process(COMMAND ${EXE} run ${SOURCE}/inputs/beam/cantilever.yaml -o ${OUT}/beam.h5 -q
                        --set time.dt=1e-4 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "traverse run (beam) failed (${rc})")
endif()
message(STATUS "rod.h5 and beam.h5 written in ${OUT}")
