#!/usr/bin/env python3
"""Side-by-side benchmark, hanging cable: traverse against PyElastica (not in CI).

Runs, in turn:
- traverse on inputs/default.yaml at ds = 0.02 (--repeat times; whole-process CPU = user +
  system of the child process, as /usr/bin/time %U+%S reports it);
- a fine traverse reference (ds = --ref-ds, default 0.00125, dt = ds / v), once;
- pyelastica_cable.py for each --n-elem (--repeat times; computing CPU = time.process_time
  around the settle and crossing loops, JIT warm-up reported apart). All PyElastica runs of one
  invocation share a fresh numba cache directory, so the first run compiles (cold JIT) and the
  others load the cache.

Errors against the reference, midspan height h(t) = y(L/2, t):
- midspan minimum: |min h - min h_ref| / |min h_ref|, each minimum taken on a cubic spline
  through that code's output samples (traverse: every step; PyElastica: every step);
- history: max over the 51 times of the ds = 0.02 grid (t_k = k T / 50; those of them that
  are output times of the run: all but for ds = 0.04) of |h(t_k) - h_ref(t_k)|, also divided
  by |min h_ref|.

Prints a Markdown table and writes summary.json to --out. Needs h5py, numpy, scipy
(Debian: python3-h5py python3-numpy python3-scipy) and, for PyElastica, numba and
PyElastica's source on PYTHONPATH (see README.md).
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile

import h5py
import numpy as np
from scipy.interpolate import CubicSpline

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


def child_cpu(cmd, env=None, cwd=None):
    """Run cmd; return (user + system CPU of the child, stdout)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit(f"failed: {' '.join(cmd)}")
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), p.stdout


# PyElastica's rod is extensible and shearable: E A, and alpha_c G A with its shear factor
# alpha_c = 27/28 (pyelastica_cable.py's data: E = 2.5e8 Pa, nu = 0.25, r = 5 mm).
PEER_SHEAR_STIFFNESS = 27.0 / 28.0 * 2.5e8 / (2.0 * 1.25) * np.pi * 0.005 ** 2
MODEL_SETS = {"inextensible": [],
              "shearable": ["--set", "rod.model=shearable", "--set", f"rod.shear_stiffness={PEER_SHEAR_STIFFNESS!r}"]}


def traverse_run(exe, ds, out, model="inextensible"):
    cmd = [exe, "run", os.path.join(REPO, "inputs", "default.yaml"),
           "--set", f"mesh.ds={ds}", "-o", out, "-q", "--overwrite", *MODEL_SETS[model]]
    cpu, _ = child_cpu(cmd)
    with h5py.File(out, "r") as f:
        t = f["time"][:]
        h = f["probes/midspan"][:, 1]
    return cpu, t, h


def spline_min(t, h):
    cs = CubicSpline(t, h)
    tt = np.linspace(t[0], t[-1], 400001)
    return float(cs(tt).min())


def errors(t, h, ref):
    t_ref, h_ref, min_ref = ref
    grid = np.linspace(0.0, t_ref[-1], 51)
    # only the grid times that are output times of the run (all of them for ds = 0.02 / m
    # and for PyElastica, whose step counts are multiples of 50; every other one for
    # ds = 0.04); np.interp only absorbs the round-off in t
    held = np.array([np.abs(t - g).min() < 1e-9 for g in grid])
    grid = grid[held]
    d = np.interp(grid, t, h) - np.interp(grid, t_ref, h_ref)
    m = spline_min(t, h)
    return {
        "min": m,
        "err_min_rel": abs(m - min_ref) / abs(min_ref),
        "err_hist_abs": float(np.abs(d).max()),
        "err_hist_rel": float(np.abs(d).max()) / abs(min_ref),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--traverse", default=os.path.join(REPO, "build", "traverse"))
    ap.add_argument("--ds", default="0.02,0.04,0.01",
                    help="traverse mesh sizes; the first is the one the ratios refer to")
    ap.add_argument("--ref-ds", type=float, default=0.00125)
    ap.add_argument("--n-elem", default="200,100", help="PyElastica element counts")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-traverse", action="store_true",
                    help="reuse summary.json's traverse figures from --out")
    ap.add_argument("--out", default="out/peers")
    ap.add_argument("--model", choices=sorted(MODEL_SETS), default="inextensible",
                    help="traverse's rod model (its runs and its reference); shearable: PyElastica's own "
                         "model, with its E A and shear stiffness (27/28) G A")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    summary_path = os.path.join(args.out, "summary.json")

    ref_file = os.path.join(args.out, f"traverse_{args.model}_ref_ds{args.ref_ds}.h5")
    if args.skip_traverse and os.path.exists(summary_path):
        summary = json.load(open(summary_path))
        with h5py.File(ref_file, "r") as f:
            t_ref, h_ref = f["time"][:], f["probes/midspan"][:, 1]
    else:
        summary = {"runs": []}
        cpu, t_ref, h_ref = traverse_run(args.traverse, args.ref_ds, ref_file, args.model)
        summary["reference"] = {"model": args.model, "ds": args.ref_ds, "steps": len(t_ref) - 1, "cpu": cpu,
                                "min": spline_min(t_ref, h_ref), "static": float(h_ref[0])}
    ref = (t_ref, h_ref, spline_min(t_ref, h_ref))

    if not args.skip_traverse:
        for ds in [float(x) for x in args.ds.split(",") if x]:
            cpus = []
            for k in range(args.repeat):
                out = os.path.join(args.out, f"traverse_{args.model}_ds{ds}.h5")
                cpu, t, h = traverse_run(args.traverse, ds, out, args.model)
                cpus.append(cpu)
            e = errors(t, h, ref)
            summary["runs"].append({
                "code": "traverse", "disc": f"{args.model}, ds = {ds} ({round(1 / ds) + 1} nodes)",
                "dt": float(t[1] - t[0]), "steps": len(t) - 1, "cpu_all": cpus,
                "cpu": statistics.median(cpus), "static": float(h[0]), **e})

    cache = tempfile.mkdtemp(prefix="numba-cache-")
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    for n in [int(x) for x in args.n_elem.split(",") if x]:
        runs = []
        for k in range(args.repeat):
            csv = os.path.join(args.out, f"pyelastica_n{n}.csv")
            _, so = child_cpu([sys.executable, os.path.join(HERE, "pyelastica_cable.py"),
                               "--n-elem", str(n), "--csv", csv], env=env)
            runs.append(json.loads(so.strip().splitlines()[-1]))
        t, h = np.loadtxt(csv, delimiter=",", skiprows=1, unpack=True)
        e = errors(t, h, ref)
        med = lambda key: statistics.median(r[key] for r in runs)
        r0 = runs[-1]
        summary["runs"] = [r for r in summary["runs"]
                           if not (r["code"] == "PyElastica" and r["n_elem"] == n)]
        summary["runs"].append({
            "code": "PyElastica", "n_elem": n, "disc": f"{n} elements",
            "dt": r0["dt"], "steps": r0["steps_crossing"], "steps_settle": r0["steps_settle"],
            "settle_time": r0["settle_time"], "static": r0["y_static"],
            "cpu_all": [r["cpu_computing"] for r in runs], "cpu": med("cpu_computing"),
            "cpu_settle": med("cpu_settle"), "cpu_crossing": med("cpu_crossing"),
            "jit_cold": runs[0]["cpu_jit_warmup"],
            "jit_warm": statistics.median(r["cpu_jit_warmup"] for r in runs[1:]) if len(runs) > 1 else None,
            **e})

    json.dump(summary, open(summary_path, "w"), indent=1)

    tr = next(r for r in summary["runs"] if r["code"] == "traverse")
    rf = summary["reference"]
    print(f"reference: traverse {rf.get('model', 'inextensible')} ds = {rf['ds']} ({rf['steps']} steps), min h = {rf['min']:.6f} m, "
          f"static h = {rf['static']:.6f} m")
    print("| code | discretisation | dt [s] | steps | CPU [s] (median) | static sag [mm] "
          "| min h [m] | error of the minimum | max history error | CPU ratio to traverse |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in summary["runs"]:
        steps = str(r["steps"]) if r["code"] == "traverse" else \
            f"{r['steps_settle']} settle + {r['steps']} crossing"
        cpu = f"{r['cpu']:.3g}" if r["code"] == "traverse" else \
            f"{r['cpu']:.3g} ({r['cpu_settle']:.3g} settle + {r['cpu_crossing']:.3g} crossing)"
        print(f"| {r['code']} | {r['disc']} | {r['dt']:.3g} | {steps} | {cpu} | "
              f"{-1000 * r['static']:.2f} | {r['min']:.5f} | {100 * r['err_min_rel']:.2f} % | "
              f"{100 * r['err_hist_rel']:.2f} % ({1000 * r['err_hist_abs']:.2f} mm) | "
              f"{r['cpu'] / tr['cpu']:.1f} |")
    for r in summary["runs"]:
        if r["code"] == "PyElastica":
            warm = "-" if r["jit_warm"] is None else f"{r['jit_warm']:.3g} s"
            print(f"PyElastica {r['n_elem']}: CPU runs {['%.3g' % c for c in r['cpu_all']]}, "
                  f"JIT warm-up of the first run {r['jit_cold']:.3g} s (cold only for the "
                  f"invocation's first run), later runs {warm}")
        else:
            print(f"traverse {r['disc']}: CPU runs {['%.3g' % c for c in r['cpu_all']]}")


if __name__ == "__main__":
    main()
