"""Run under `mpiexec -n N`: every rank runs the scene through traverse.run, distributed over
MPI_COMM_WORLD, into OUT; rank 0 then compares OUT with REFERENCE (the executable's run of
the same scene on N ranks) dataset by dataset, bit for bit.

    mpiexec -n 2 python3 check_mpi.py SCENE REFERENCE.h5 OUT.h5 [KEY=VALUE ...]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import traverse  # noqa: E402
from conftest import assert_same_datasets  # noqa: E402


def main():
    scene_file, reference, out, *sets = sys.argv[1:]
    result = traverse.run(traverse.Scene.load(scene_file, overrides=sets), output=out, overwrite=True)
    from mpi4py import MPI  # MPI is running (started by traverse.run): mpi4py only asks the rank

    comm = MPI.COMM_WORLD
    failure = None
    if comm.Get_rank() == 0:
        try:
            n = assert_same_datasets(reference, out)
            print(f"{comm.Get_size()} ranks: {n} datasets equal bit for bit, {result.steps} output steps, "
                  f"status {result.status}")
        except BaseException as e:  # pytest's failure too: every rank ends with the outcome
            failure = f"{type(e).__name__}: {e}"
    failure = comm.bcast(failure, root=0)
    if failure:
        if comm.Get_rank() == 0:
            print(failure, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
