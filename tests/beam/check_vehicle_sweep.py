"""Sweeps of the vehicle scenes on 1 and on 2 MPI ranks (the cases spread over the ranks): every
case completes, the index's summaries agree between the rank counts to the last digit (each case
runs whole in one rank), and a case equals the same scene run alone (traverse run): its peak
over every time step (the probe's attributes min and max), of which the written steps' peak is
a sample.
Usage: check_vehicle_sweep.py MPIEXEC TRAVERSE SOURCE_DIR OUT_DIR     (exit status 1 on any failure)
"""
import csv
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

failed = 0


def check(cond, what):
    global failed
    print(("ok    " if cond else "FAIL  ") + what)
    failed += not cond


def sweep(mpiexec, exe, scene, out, ranks, vary, summary):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [mpiexec, "-n", str(ranks), "--oversubscribe", exe, "sweep", scene, "-o", out, "--vary", vary,
           "--summary", summary, "-q"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    print(" ".join(cmd) + "\n" + r.stdout + r.stderr)
    with open(os.path.join(out, "index.csv"), newline="") as fh:
        return r.returncode, list(csv.DictReader(fh))


def main():
    mpiexec, exe, src, out = sys.argv[1:5]
    cases = [("sprung_mass.yaml", "loads.car.speed=20,25,30", "midspan:absmax"),
             ("two_axle_car.yaml", "loads.car.speed=20,30", "car_body_acceleration:absmax"),
             ("axle_train.yaml", "loads.train.speed=60,73.6", "deck:absmax")]
    for scene, vary, summary in cases:
        path = os.path.join(src, "inputs", "beam", scene)
        results = {}
        for ranks in (1, 2):
            rc, rows = sweep(mpiexec, exe, path, os.path.join(out, f"{scene}.{ranks}"), ranks, vary, summary)
            check(rc == 0 and all(r["status"] == "complete" for r in rows), f"{scene}: {ranks} rank(s), every case complete")
            results[ranks] = [r[summary] for r in rows]
        check(results[1] == results[2], f"{scene}: the summaries on 1 and 2 ranks agree: {results[1]}")
        # The last case against the scene run alone.
        key, values = vary.split("=")
        alone = os.path.join(out, f"{scene}.alone.h5")
        r = subprocess.run([exe, "run", path, "-o", alone, "--overwrite", "-q", "--set", f"{key}={values.split(',')[-1]}"],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"{scene}: traverse run of the last case")
        probe, _ = summary.split(":")
        with h5py.File(alone, "r") as f:
            d = f["probes"][probe]
            peak = float(max(abs(d.attrs["min"][0]), abs(d.attrs["max"][0])))
            written = float(np.nanmax(np.abs(d[:])))
        check(abs(peak - float(results[1][-1])) <= 1e-12 * peak, f"{scene}: the run alone gives {peak!r} ({results[1][-1]})")
        check(written <= peak, f"{scene}: the written steps' peak {written!r} is a sample of it")
    print(f"{failed} failure(s)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
