#!/usr/bin/env python3
"""Work-precision of the rod's time stepping (docs/adaptive.md, docs/benchmarks.md): the error
of a trace against a reference run, against the CPU time of the whole process, for
  fixed   dt = the scene's output interval (ds / v for the reference scenes),
  refined fixed dt divided by 2, 4, ...,
  adaptive (time.adaptive) at several tolerances,
all writing at the same output times (the adaptive steps land on them), so the traces compare
point for point.

Studies (--study):
  cable    hanging cable (inputs/default.yaml, ds = 0.01): midspan trace, the whole crossing;
           reference: fixed dt = ds / (64 v).
  cable-20 the same cable under 20 N (inputs/rod/hanging_cable_F20_a0.5.yaml, ds = 0.01): the
           deep V that travels with the load; reference as for cable.
  arch     shallow arch at v = 0.02 m/s (inputs/arch/shallow_arch_v0.02.yaml at ds = 0.01, the
           scene's rho_inf = 0.8), to t = 16.5 s: the snap position (the load position where the
           right end has turned through half its initial inclination, interpolated between output
           steps every 0.0625 s, or every step when dt is longer); reference: fixed dt / 256,
           output every step.
  arch-undamped  the same at rho_inf = 1 and v = 0.5 m/s (ds = 0.01, the whole crossing): the
           midpoint trace; reference: fixed dt = ds / (256 v).
  arch-undamped-snap  the same scene to t = 1.2 s: the snap position (as in arch, outputs every
           0.0025 s = 1.25 mm of load travel); reference: fixed dt = ds / (256 v), output every step.

Usage: work_precision.py --traverse BUILD/traverse --study cable|cable-20|arch|arch-undamped|arch-undamped-snap [--out DIR]
       [--loaded] [--plot-only]
Writes DIR/<study>.csv (method, parameter, cpu_s, steps, error) and DIR/<study>.png.
"""
import argparse
import csv
import os
import resource
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "..", "inputs")

STUDIES = {
    "cable": {
        "scene": os.path.join(INPUTS, "default.yaml"),
        "sets": [],
        "dt": 0.01 / 3.63418,
        "probe": "midspan",
        "refine": [1, 2, 4, 8],
        "tolerances": [1e-2, 1e-3, 1e-4, 1e-5],
        "reference": ("fixed", 64),
    },
    "arch": {
        "scene": os.path.join(INPUTS, "arch", "shallow_arch_v0.02.yaml"),
        "sets": ["mesh.ds=0.01", "time.end=16.5", "output.fields=[]"],
        "dt": 0.5,
        "metric": "snap",
        "output_interval": 0.0625,
        "refine": [1, 4, 16, 64],
        "tolerances": [1e-2, 1e-3, 1e-4],
        "reference": ("fixed", 256),
    },
    "arch-undamped": {
        "scene": os.path.join(INPUTS, "arch", "shallow_arch_v0.5.yaml"),
        "sets": ["scheme.rho_inf=1", "output.fields=[]"],
        "dt": 0.02,
        "probe": "midpoint",
        "refine": [1, 4, 16, 64],
        "tolerances": [1e-2, 1e-3, 1e-4, 1e-5],
        "reference": ("fixed", 256),
    },
}
# The cable under 20 N: the default scene's study on its F = 20 N scene.
STUDIES["cable-20"] = {**STUDIES["cable"], "scene": os.path.join(INPUTS, "rod", "hanging_cable_F20_a0.5.yaml")}
# The undamped arch to just after the snap, the snap position as metric (outputs 1.25 mm of load travel apart).
STUDIES["arch-undamped-snap"] = {
    **{k: v for k, v in STUDIES["arch-undamped"].items() if k != "probe"},
    "sets": STUDIES["arch-undamped"]["sets"] + ["time.end=1.2"],
    "metric": "snap",
    "output_interval": 0.0025,
}


LOADED = []  # --loaded: ["initial_state.loaded=true"] (the arch starts in equilibrium with the load)


def run(exe, study, method, param, out_dir):
    """Runs one case; returns (path, cpu seconds of the whole process, steps)."""
    s = STUDIES[study]
    name = f"{study}_{method}_{param:g}.h5"
    path = os.path.join(out_dir, name)
    cmd = [exe, "run", s["scene"], "-o", path, "--overwrite"]
    for kv in s["sets"] + LOADED:
        cmd += ["--set", kv]
    interval = s.get("output_interval", s["dt"])  # the output times (snap metric: denser than dt)
    if method == "fixed":
        dt = s["dt"] / param
        every = max(1, int(round(interval / dt))) if param != s["reference"][1] or "output_interval" not in s else 1
        cmd += ["--set", f"time.dt={dt:.17g}", "--set", f"output.every={every}"]
    else:
        cmd += ["--set", f"time.dt={interval:.17g}", "--set", f"time.adaptive.tolerance={param:g}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        sys.exit(f"work_precision.py: {' '.join(cmd)} failed ({res.returncode}):\n{res.stdout}{res.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    steps = None
    for line in res.stdout.splitlines():
        if line.startswith("adaptive: "):
            steps = int(line.split()[1])
        elif " steps of dt = " in line and steps is None:
            steps = int(line.split(" steps of dt = ")[0].split()[-1])
    return path, cpu, steps


def trace(path, probe):
    out = traverse_io.load(path)
    return np.asarray(out.time, dtype=float), np.asarray(out.probes[probe], dtype=float)


def snap_position(path):
    """The load position sigma [m] where the right end of the shallow arch has turned through
    half its initial inclination (the middle of the snap), interpolated between output steps."""
    import arches
    out = traverse_io.load(path)
    theta, alpha0 = arches.right_end_rotation(out)
    sig = traverse_io.first_load_sigma(out)
    k = np.nonzero(theta >= 0.5 * alpha0)[0]
    if not k.size:
        sys.exit(f"work_precision.py: {path}: the arch did not snap")
    k = int(k[0])
    f = (0.5 * alpha0 - theta[k - 1]) / (theta[k] - theta[k - 1])
    return float(sig[k - 1] + f * (sig[k] - sig[k - 1]))


def study_rows(exe, study, out_dir):
    s = STUDIES[study]
    kind, p = s["reference"]
    ref_path, _, _ = run(exe, study, kind, p, out_dir)
    snap = s.get("metric") == "snap"
    if snap:
        sig_ref = snap_position(ref_path)
        print(f"{study}: reference snap at sigma = {sig_ref:.6f} m", flush=True)
    else:
        t_ref, x_ref = trace(ref_path, s["probe"])
    rows = []
    cases = [("fixed", k) for k in s["refine"]] + [("adaptive", tol) for tol in s["tolerances"]]
    for method, param in cases:
        path, cpu, steps = run(exe, study, method, param, out_dir)
        if snap:
            err = abs(snap_position(path) - sig_ref)
            rows.append({"method": method, "parameter": param, "cpu_s": cpu, "steps": steps, "error": err})
            print(f"{study}: {method:8s} {param:<8g} cpu {cpu:7.2f} s  steps {steps:7d}  snap error {err:.3e} m",
                  flush=True)
            continue
        t, x = trace(path, s["probe"])
        if len(t) != len(t_ref) or np.abs(t - t_ref).max() > 1e-9:
            sys.exit(f"work_precision.py: {path}: output times differ from the reference's")
        err = float(np.linalg.norm(x - x_ref, axis=1).max())
        rows.append({"method": method, "parameter": param, "cpu_s": cpu, "steps": steps, "error": err})
        print(f"{study}: {method:8s} {param:<8g} cpu {cpu:7.2f} s  steps {steps:7d}  error {err:.3e} m", flush=True)
    return rows


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["method", "parameter", "cpu_s", "steps", "error"])
        w.writeheader()
        for r in rows:
            w.writerow(r)


def read_csv(path):
    with open(path) as f:
        return [{"method": r["method"], "parameter": float(r["parameter"]), "cpu_s": float(r["cpu_s"]),
                 "steps": int(r["steps"]), "error": float(r["error"])} for r in csv.DictReader(f)]


def plot(rows, study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for method, style, label in [("fixed", "o-", "fixed dt (ds/v, /2, /4, ...)"), ("adaptive", "s-", "adaptive")]:
        rs = [r for r in rows if r["method"] == method]
        ax.loglog([r["cpu_s"] for r in rs], [r["error"] for r in rs], style, label=label)
        for r in rs:
            txt = f"/{int(r['parameter'])}" if method == "fixed" else f"{r['parameter']:g}"
            ax.annotate(txt, (r["cpu_s"], r["error"]), textcoords="offset points", xytext=(4, 4), fontsize=7)
    ax.set_xlabel("CPU time of the whole process [s]")
    ax.set_ylabel("|error| of the snap position sigma [m]" if STUDIES[study].get("metric") == "snap"
                  else f"max |error| of the {STUDIES[study]['probe']} trace [m]")
    ax.set_title(f"work-precision: {study}" + (" (start loaded)" if LOADED else ""))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse", required=True)
    ap.add_argument("--study", choices=sorted(STUDIES), required=True)
    ap.add_argument("--out", default="work_precision")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--loaded", action="store_true",
                    help="arch studies: initial_state.loaded=true (the start in equilibrium with the load at t = 0)")
    a = ap.parse_args(argv)
    if a.loaded:
        if not a.study.startswith("arch"):
            sys.exit("work_precision.py: --loaded applies to the arch studies")
        LOADED.append("initial_state.loaded=true")
    os.makedirs(a.out, exist_ok=True)
    csv_path = os.path.join(a.out, f"{a.study}.csv")
    rows = read_csv(csv_path) if a.plot_only else study_rows(os.path.abspath(a.traverse), a.study, a.out)
    if not a.plot_only:
        write_csv(rows, csv_path)
    plot(rows, a.study, os.path.join(a.out, f"{a.study}.png"))
    print(f"wrote {csv_path} and {os.path.join(a.out, a.study + '.png')}")


if __name__ == "__main__":
    main()
