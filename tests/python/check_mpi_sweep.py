"""Run under `mpiexec -n N`: traverse.sweep with every rank calling it (the cases spread over
MPI_COMM_WORLD) gives, on every rank, the table of REFERENCE_DIR/index.csv (the executable's
sweep of the same cases); then a rod run with a step callback on N ranks: rank 0 sees the
whole rod (the file's r at the output steps), and returning False stops every rank; the same
for a beam run (inputs/beam/cantilever.yaml next to SCENE): rank 0 sees the deflection the
file holds.

    mpiexec -n 2 python3 check_mpi_sweep.py SCENE REFERENCE_DIR OUT_DIR SUMMARY KEY=VALUES [SET ...]
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import traverse  # noqa: E402


def check_sweep(scene, reference, out, summary, vary):
    key, values = vary.split("=", 1)
    table = traverse.sweep(scene, vary={key: values}, summary=summary, output=out, overwrite=True)
    with open(os.path.join(reference, "index.csv"), newline="") as f:
        index = list(csv.DictReader(f))
    assert len(table) == len(index), (len(table), len(index))
    for row, ref in zip(table, index):
        assert row["case"] == int(ref["case"]) and float(row[key]) == float(ref[key]), (row, ref)
        assert (row["status"], row["exit_code"], row["message"]) == (ref["status"], int(ref["exit_code"]), ref["message"])
        assert row[summary] == float(ref[summary]), (row[summary], ref[summary])
    # Without a directory: the same numbers, on every rank, and nothing left.
    again = traverse.sweep(scene, vary={key: values}, summary=summary)
    assert [r[summary] for r in again] == [r[summary] for r in table] and again.directory is None
    return table


def check_callback(scene, out):
    seen = []
    result = traverse.run(scene, output=out, overwrite=True, every=2, callback=seen.append)
    times = list(result.time)
    r = result.fields["r"]
    matched = 0
    for s in seen:
        assert s.r.shape == (r.shape[1], 3)
        if s.t in times:
            np.testing.assert_array_equal(s.r, r[times.index(s.t)])
            matched += 1
    stopped = traverse.run(scene, output=out, overwrite=True, every=2, callback=lambda s: s.step < 4)
    assert stopped.interrupted and "stopped by the step callback" in stopped.status, stopped.status
    return len(seen), matched


def check_beam_callback(scene_file, out):
    beam = traverse.Scene.load(os.path.join(os.path.dirname(scene_file), "beam", "cantilever.yaml"),
                               overrides=["time.dt=1e-4", "output.every=1"])
    seen = []
    result = traverse.run(beam, output=out, overwrite=True, every=2, callback=seen.append)
    w = result.fields["deflection"]
    for s in seen:
        assert result.time[s.step] == s.t, (s.step, s.t)
        np.testing.assert_array_equal(s.w, w[s.step].reshape(-1))
    stopped = traverse.run(beam, output=out, overwrite=True, every=2, callback=lambda s: s.step < 4)
    assert stopped.interrupted and stopped.steps == 5, (stopped.status, stopped.steps)
    return len(seen)


def main():
    scene_file, reference, out, summary, vary, *sets = sys.argv[1:]
    scene = traverse.Scene.load(scene_file, overrides=sets)
    failure = table = None
    try:
        table = check_sweep(scene, reference, os.path.join(out, "sweep"), summary, vary)
    except BaseException as e:
        failure = f"{type(e).__name__}: {e}"
    # MPI is running (started by traverse.sweep): mpi4py only asks the rank, and traverse ends it.
    from mpi4py import MPI  # noqa: E402

    comm = MPI.COMM_WORLD
    try:
        if failure:
            raise RuntimeError(failure)
        seen, matched = check_callback(scene, os.path.join(out, "callback.h5"))
        beam_seen = check_beam_callback(scene_file, os.path.join(out, "beam_callback.h5"))
        rows = comm.gather([(r["case"], r["status"], r[summary]) for r in table], root=0)
        if comm.Get_rank() == 0:
            assert all(x == rows[0] for x in rows), "the table differs between ranks"
            assert seen > 0 and matched > 0 and beam_seen > 0, (seen, matched, beam_seen)
            print(f"{comm.Get_size()} ranks: sweep of {len(table)} cases equals the executable's index; "
                  f"callback saw {seen} steps, {matched} compared with the file; beam callback {beam_seen} steps")
        else:
            assert seen == 0 and beam_seen == 0, f"rank {comm.Get_rank()} called the callback"
    except BaseException as e:  # every rank ends with the outcome
        failure = f"rank {comm.Get_rank()}: {type(e).__name__}: {e}"
    failures = [f for f in comm.allgather(failure) if f]
    if failures:
        if comm.Get_rank() == 0:
            print("\n".join(failures), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
