#!/usr/bin/env python3
"""Run time against error for the hinged-arch reference scenes (a benchmark, not a test).

Runs the traverse executable on the shipped arch scenes over a sweep of ds (dt = ds / v,
time.dt: auto) for each solver / path variant, and compares the quantity the figures show
with the finest run of the same variant:

  shallow_v5    inputs/arch/shallow_arch_v5.0.yaml (F = 2 N at 5 m/s, no snap): midpoint
                height y(L/2) against time; planar path (auto) and 3D path (scheme.planar: off)
  deep_v0.05    inputs/arch/deep_arch_v0.05.yaml (F = 3.8 N at 0.05 m/s, lateral trigger):
                lateral midpoint displacement x(L/2) against time (3D; the trigger makes it
                non-planar), and the in-plane y(L/2)

Error = max over the output times of the coarsest run (every finer run contains them) of
|q(t) - q_ref(t)|, q_ref from the finest ds of the same variant. Run time = the executable's
own "time stepping" figure (wall time of the time steps and their output; the arch formation,
set-up and start-up are excluded), with the probes as the only output (output.fields: [])
and no restart points between (--restart-interval 1e9): on these small meshes writing a
restart point after every output step (the default) costs more than the step itself.
Solvers: the default (block-tridiagonal LU, direct) and KLU2.

usage: bench_arches.py TRAVERSE_EXE [--quick] [--csv FILE] [--ranks N]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

CASES = {
    "shallow_v5": dict(scene="inputs/arch/shallow_arch_v5.0.yaml", quantities=[("midpoint", 1, "y(L/2) [m]")],
                       variants=[("auto", "planar", []), ("auto", "3D", ["scheme.planar=off"]),
                                 ("KLU2", "planar", ["solver.Linear Solver=KLU2"]),
                                 ("KLU2", "3D", ["solver.Linear Solver=KLU2", "scheme.planar=off"])]),
    "deep_v0.05": dict(scene="inputs/arch/deep_arch_v0.05.yaml",
                       quantities=[("midpoint", 0, "x(L/2) [m]"), ("midpoint", 1, "y(L/2) [m]")],
                       variants=[("auto", "3D", []), ("KLU2", "3D", ["solver.Linear Solver=KLU2"])]),
}


def run(exe, scene, ds, sets, ranks, out, quantities):
    cmd = [exe, "run", os.path.join(ROOT, scene), "-o", out, "--overwrite", "--set", f"mesh.ds={ds}",
           "--set", "output.every=1", "--set", "output.fields=[]", "--restart-interval", "1e9", "-v"]
    for s in sets:
        cmd += ["--set", s]
    if ranks > 1:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(ranks)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
    n = re.search(r"(\d+) Newton iterations in (\d+) solves", p.stdout)  # -v
    s = re.search(r"time stepping ([0-9.eE+-]+) s", p.stdout)
    if not n or not s:
        raise RuntimeError(f"no timing line in the output of {' '.join(cmd)}:\n{p.stdout}")
    with h5py.File(out, "r") as f:
        t = np.array(f["time"])
        q = [np.array(f["probes"][probe])[:, comp] for probe, comp, _ in quantities]
        path = f.attrs.get("rod_path", "")
    return dict(t=t, q=q, newton=int(n.group(1)), steps=int(n.group(2)), seconds=float(s.group(1)),
                path=path.decode() if isinstance(path, bytes) else str(path))


def at_times(t_ref, q_ref, t):
    """q_ref at the times t (each t must be one of t_ref's, to round-off)."""
    idx = np.searchsorted(t_ref, t - 1e-9 * max(1.0, t_ref[-1]))
    idx = np.clip(idx, 0, len(t_ref) - 1)
    if np.max(np.abs(t_ref[idx] - t)) > 1e-7 * max(1.0, t_ref[-1]):
        raise RuntimeError("output times do not nest")
    return q_ref[idx]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--quick", action="store_true", help="ds down to 0.005 (reference 0.005), not 0.0025")
    ap.add_argument("--csv", default="")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--cases", default=",".join(CASES))
    a = ap.parse_args()
    sweep = [0.04, 0.02, 0.01, 0.005] if a.quick else [0.04, 0.02, 0.01, 0.005, 0.0025]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.cases.split(","):
            c = CASES[name]
            for solver, path, sets in c["variants"]:
                res = {}
                for ds in sweep:
                    res[ds] = run(a.exe, c["scene"], ds, sets, a.ranks, os.path.join(tmp, f"{name}.h5"),
                                  c["quantities"])
                    if res[ds]["path"] != path:
                        raise RuntimeError(f"{name} {solver} {path}: ran on the '{res[ds]['path']}' path")
                ref = res[sweep[-1]]
                t0 = res[sweep[0]]["t"]
                for qi, (_, _, label) in enumerate(c["quantities"]):
                    errs = []
                    for ds in sweep[:-1]:
                        r = res[ds]
                        err = float(np.max(np.abs(at_times(r["t"], r["q"][qi], t0) -
                                                  at_times(ref["t"], ref["q"][qi], t0))))
                        errs.append(err)
                        rows.append(dict(case=name, quantity=label, solver=solver, path=path, ranks=a.ranks, ds=ds,
                                         steps=r["steps"], newton=r["newton"], run_seconds=r["seconds"], error=err,
                                         reference_ds=sweep[-1], max_abs_q=float(np.max(np.abs(ref["q"][qi])))))
                        print(f"{name:11s} {label:11s} {solver:5s} {path:6s} ranks {a.ranks} ds {ds:<7g} steps "
                              f"{r['steps']:5d} Newton {r['newton']:6d} run {r['seconds']:9.3f} s  max|dq| {err:.3e}",
                              flush=True)
                    if len(errs) >= 3 and min(errs[-3:]) > 0:
                        p = np.log2(errs[-3] / errs[-2]), np.log2(errs[-2] / errs[-1])
                        print(f"{name:11s} {label:11s} {solver:5s} {path:6s} observed orders (halved ds): "
                              f"{p[0]:.2f}, {p[1]:.2f}", flush=True)
    if a.csv:
        new = not os.path.exists(a.csv)
        with open(a.csv, "a", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            if new:
                w.writeheader()
            w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
