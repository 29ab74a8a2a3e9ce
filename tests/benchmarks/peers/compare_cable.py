#!/usr/bin/env python3
"""Side-by-side benchmark, cables: traverse against PyElastica (not in CI).

Two scenes (--scene):
- cable: the hanging cable, inputs/default.yaml, against pyelastica_cable.py;
- taut: the taut span, traverse_taut.yaml (inputs/rod/taut_span_robot.yaml with the robot's
  weight as a moving force, PyElastica's shearable model, undamped), against
  pyelastica_taut.py.

Runs, in turn:
- traverse at each --ds (--repeat times; whole-process CPU = user + system of the child
  process, as /usr/bin/time %U+%S reports it); time step: cable ds / v (time.dt auto), taut
  ds / (--dt-ratio v);
- a fine traverse reference (ds = --ref-ds, the same dt / ds), once;
- the PyElastica scene for each --n-elem (--repeat times; computing CPU = time.process_time
  around the settle and crossing loops, JIT warm-up reported apart). All PyElastica runs of one
  invocation share a fresh numba cache directory, so the first run compiles (cold JIT) and the
  others load the cache.

Errors against the reference, midspan height h(t) = y(L/2, t), both divided by a scale D:
cable: D = |min h_ref| (the sag under the load, from the supports' level); taut: D = h_ref(0)
- min h_ref (the deflection the load adds to the static sag):
- midspan minimum: |min h - min h_ref| / D, each minimum taken on a cubic spline through that
  code's output samples (traverse: every step; PyElastica: every step);
- history: max over the times of a grid t_k = k T / m (cable: m = 50, T = L / v, the ds = 0.02
  steps; taut: m = 200, every 0.01 s) of |h(t_k) - h_ref(t_k)| / D, over those t_k that are
  output times of the run (all of them but for the coarsest traverse meshes).

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

# What differs between the scenes. model_sets: traverse's --set options for each --model
# (the taut scene file is already PyElastica's shearable model). scale: D, "min" (|min h_ref|)
# or "deflection" (h_ref(0) - min h_ref). speed: the load's, set in both codes (--speed);
# None: the scene file's. dt_ratio: traverse's dt = ds / (dt_ratio v), 1 = time.dt auto.
SCENES = {
    "cable": {
        "scene": os.path.join(REPO, "inputs", "default.yaml"),
        "peer": "pyelastica_cable.py",
        "length": 1.0,
        "model_sets": {
            "inextensible": [],
            "shearable": ["--set", "rod.model=shearable",
                          "--set", f"rod.shear_stiffness={PEER_SHEAR_STIFFNESS!r}"]},
        "model": "inextensible", "ds": "0.02,0.04,0.01", "ref_ds": 0.00125, "n_elem": "200,100",
        "grid": 50, "scale": "min", "speed": None, "dt_ratio": 1.0, "prefix": "",
    },
    "taut": {
        "scene": os.path.join(HERE, "traverse_taut.yaml"),
        "peer": "pyelastica_taut.py",
        "length": 20.0,
        "model_sets": {"shearable": []},
        "model": "shearable", "ds": "0.1,0.4,0.2,0.05,0.025,0.0125", "ref_ds": 0.00625,
        "n_elem": "100,200", "grid": 200, "scale": "deflection", "speed": 10.0, "dt_ratio": 4.0,
        "prefix": "taut_",
    },
}


def traverse_run(exe, sc, ds, out, model, speed, dt_ratio):
    sets = ["--set", f"mesh.ds={ds}", *sc["model_sets"][model]]
    if speed is not None:
        sets += ["--set", f"loads.F.speed={speed!r}"]
    if dt_ratio != 1.0:
        sets += ["--set", f"time.dt={ds / (dt_ratio * speed)!r}"]
    cmd = [exe, "run", sc["scene"], "-o", out, "-q", "--overwrite", *sets]
    cpu, _ = child_cpu(cmd)
    with h5py.File(out, "r") as f:
        t = f["time"][:]
        h = f["probes/midspan"][:, 1]
    return cpu, t, h


def spline_min(t, h):
    cs = CubicSpline(t, h)
    tt = np.linspace(t[0], t[-1], 400001)
    return float(cs(tt).min())


def reference(t_ref, h_ref, scale):
    """(t_ref, h_ref, min h_ref, D)."""
    m = spline_min(t_ref, h_ref)
    return t_ref, h_ref, m, abs(m) if scale == "min" else float(h_ref[0]) - m


def errors(t, h, ref, grid_intervals):
    t_ref, h_ref, min_ref, scale = ref
    grid = np.linspace(0.0, t_ref[-1], grid_intervals + 1)
    # only the grid times that are output times of the run (all of them for the finer
    # traverse meshes and for PyElastica, whose step counts are multiples of the grid's
    # intervals); np.interp only absorbs the round-off in t
    held = np.array([np.abs(t - g).min() < 1e-9 for g in grid])
    grid = grid[held]
    d = np.interp(grid, t, h) - np.interp(grid, t_ref, h_ref)
    m = spline_min(t, h)
    return {
        "min": m,
        "err_min_rel": abs(m - min_ref) / scale,
        "err_hist_abs": float(np.abs(d).max()),
        "err_hist_rel": float(np.abs(d).max()) / scale,
        "grid_times": int(held.sum()),
    }


def at_least_as_accurate(runs, r, key):
    """The cheapest traverse run whose error (key) is at most r's, or None."""
    ok = [q for q in runs if q["code"] == "traverse" and q[key] <= r[key]]
    return min(ok, key=lambda q: q["cpu"]) if ok else None


def cpu_at_error(runs, err, key):
    """traverse's CPU at error err: log-log interpolation between the two runs around it on
    the work-precision front (the runs more accurate than every cheaper one); the cheapest
    run's CPU above the front's largest error; None below its smallest."""
    front = []
    for q in sorted((q for q in runs if q["code"] == "traverse"), key=lambda q: q["cpu"]):
        if not front or q[key] < front[-1][0]:
            front.append((q[key], q["cpu"]))
    if err >= front[0][0]:
        return front[0][1]
    for (e0, c0), (e1, c1) in zip(front, front[1:]):
        if e1 <= err <= e0:
            w = np.log(err / e0) / np.log(e1 / e0)
            return float(np.exp((1.0 - w) * np.log(c0) + w * np.log(c1)))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", choices=sorted(SCENES), default="cable")
    ap.add_argument("--traverse", default=os.path.join(REPO, "build", "traverse"))
    ap.add_argument("--ds", help="traverse mesh sizes; the first is the one the ratios refer to "
                                 "(default: cable 0.02,0.04,0.01; taut 0.1,0.4,0.2,0.05,0.025,0.0125); "
                                 "taut: DS:RATIO gives that run dt = DS / (RATIO v)")
    ap.add_argument("--ref-dt-ratio", type=float, help="taut: the reference's dt = ref-ds / (ratio v) "
                                                        "(default: --dt-ratio)")
    ap.add_argument("--ref-ds", type=float, help="the reference's ds (cable 0.00125, taut 0.00625)")
    ap.add_argument("--n-elem", help="PyElastica element counts (default 200,100 / 100,200; "
                                     "with --skip-traverse, \"\" reprints the table)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-traverse", action="store_true",
                    help="reuse summary.json's traverse figures from --out")
    ap.add_argument("--out", help="output directory (default out/peers, out/peers-taut)")
    ap.add_argument("--model", help="traverse's rod model (its runs and its reference): cable "
                    "inextensible (default) or shearable, PyElastica's own model, with its E A and "
                    "shear stiffness (27/28) G A; taut shearable")
    ap.add_argument("--speed", type=float, help="taut: the load's speed [m/s] (default 10)")
    ap.add_argument("--dt-ratio", type=float,
                    help="taut: traverse's dt = ds / (ratio v) (default 4; 1: time.dt auto)")
    args = ap.parse_args()
    sc = SCENES[args.scene]
    ds_list = args.ds or sc["ds"]
    ref_ds = args.ref_ds or sc["ref_ds"]
    n_elem = sc["n_elem"] if args.n_elem is None else args.n_elem  # "": no PyElastica runs
    out_dir = args.out or ("out/peers" if args.scene == "cable" else f"out/peers-{args.scene}")
    model = args.model or sc["model"]
    if model not in sc["model_sets"]:
        ap.error(f"--model for --scene {args.scene}: one of {sorted(sc['model_sets'])}")
    if sc["speed"] is None and (args.speed is not None or args.dt_ratio is not None or args.ref_dt_ratio is not None):
        ap.error("--speed and --dt-ratio are for --scene taut")
    speed = args.speed or sc["speed"]
    dt_ratio = args.dt_ratio or sc["dt_ratio"]
    ref_ratio = args.ref_dt_ratio or dt_ratio
    # "ds" or "ds:ratio" (taut: that run's dt = ds / (ratio v))
    runs = [(float(x.split(":")[0]), float(x.split(":")[1])) if ":" in x else (float(x), dt_ratio)
            for x in ds_list.split(",") if x]
    if sc["speed"] is None and any(ratio != dt_ratio for _, ratio in runs):
        ap.error("--ds DS:RATIO is for --scene taut")
    os.makedirs(out_dir, exist_ok=True)
    summary_path = os.path.join(out_dir, "summary.json")
    stem = os.path.join(out_dir, f"traverse_{sc['prefix']}{model}")

    ref_file = f"{stem}_ref_ds{ref_ds}" + (f"_r{ref_ratio:g}" if ref_ratio != dt_ratio else "") + ".h5"
    if args.skip_traverse and os.path.exists(summary_path):
        summary = json.load(open(summary_path))
        with h5py.File(ref_file, "r") as f:
            t_ref, h_ref = f["time"][:], f["probes/midspan"][:, 1]
    else:
        summary = {"runs": []}
        cpu, t_ref, h_ref = traverse_run(args.traverse, sc, ref_ds, ref_file, model, speed, ref_ratio)
        summary["reference"] = {"scene": args.scene, "model": model, "ds": ref_ds,
                                "steps": len(t_ref) - 1, "dt": float(t_ref[1] - t_ref[0]), "cpu": cpu,
                                "min": spline_min(t_ref, h_ref), "static": float(h_ref[0])}
    ref = reference(t_ref, h_ref, sc["scale"])
    summary["reference"]["scale"] = ref[3]

    if not args.skip_traverse:
        for ds, ratio in runs:
            cpus = []
            for k in range(args.repeat):
                out = f"{stem}_ds{ds}_r{ratio:g}.h5"
                cpu, t, h = traverse_run(args.traverse, sc, ds, out, model, speed, ratio)
                cpus.append(cpu)
            e = errors(t, h, ref, sc["grid"])
            disc = f"{model}, ds = {ds} ({round(sc['length'] / ds) + 1} nodes)"
            if ratio != dt_ratio:
                disc += f", dt = ds / ({ratio:g} v)"
            summary["runs"].append({
                "code": "traverse", "disc": disc,
                "dt": float(t[1] - t[0]), "steps": len(t) - 1, "cpu_all": cpus,
                "cpu": statistics.median(cpus), "static": float(h[0]), **e})

    cache = tempfile.mkdtemp(prefix="numba-cache-")
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    peer_args = [] if sc["speed"] is None else ["--speed", repr(speed)]
    for n in [int(x) for x in n_elem.split(",") if x]:
        runs = []
        for k in range(args.repeat):
            csv = os.path.join(out_dir, f"pyelastica_{sc['prefix']}n{n}.csv")
            _, so = child_cpu([sys.executable, os.path.join(HERE, sc["peer"]),
                               "--n-elem", str(n), "--csv", csv, *peer_args], env=env)
            runs.append(json.loads(so.strip().splitlines()[-1]))
        t, h = np.loadtxt(csv, delimiter=",", skiprows=1, unpack=True)
        e = errors(t, h, ref, sc["grid"])
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
    print(f"reference: traverse {rf.get('model', 'inextensible')} ds = {rf['ds']} ({rf['steps']} steps), "
          f"min h = {rf['min']:.6f} m, static h = {rf['static']:.6f} m, error scale D = {rf['scale']:.6f} m "
          f"({'|min h_ref|' if sc['scale'] == 'min' else 'h_ref(0) - min h_ref'})")
    print("| code | discretisation | dt [s] | steps | CPU [s] (median) | static sag [mm] "
          "| min h [m] | error of the minimum | max history error | CPU ratio to traverse |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in summary["runs"]:
        steps = str(r["steps"]) if r["code"] == "traverse" else \
            f"{r['steps_settle']} settle + {r['steps']} crossing"
        cpu = f"{r['cpu']:.3g}" if r["code"] == "traverse" else \
            f"{r['cpu']:.3g} ({r['cpu_settle']:.3g} settle + {r['cpu_crossing']:.3g} crossing)"
        print(f"| {r['code']} | {r['disc']} | {r['dt']:.3g} | {steps} | {cpu} | "
              f"{-1000 * r['static']:.2f} | {r['min']:.5f} | {100 * r['err_min_rel']:.3g} % | "
              f"{100 * r['err_hist_rel']:.3g} % ({1000 * r['err_hist_abs']:.3g} mm) | "
              f"{r['cpu'] / tr['cpu']:.1f} |")
    for r in summary["runs"]:
        if r["code"] == "PyElastica":
            warm = "-" if r["jit_warm"] is None else f"{r['jit_warm']:.3g} s"
            print(f"PyElastica {r['n_elem']}: CPU runs {['%.3g' % c for c in r['cpu_all']]}, "
                  f"JIT warm-up of the first run {r['jit_cold']:.3g} s (cold only for the "
                  f"invocation's first run), later runs {warm}")
            for key, what in (("err_hist_rel", "history"), ("err_min_rel", "minimum")):
                q = at_least_as_accurate(summary["runs"], r, key)
                if q is not None:
                    print(f"  the cheapest traverse run with at most its {what} error: {q['disc']}, "
                          f"{100 * q[key]:.3g} %, CPU {q['cpu']:.3g} s: {r['cpu'] / q['cpu']:.0f} times less")
                c = cpu_at_error(summary["runs"], r[key], key)
                if c is not None:
                    print(f"  traverse at its {what} error ({100 * r[key]:.3g} %), interpolated: "
                          f"CPU {c:.3g} s: {r['cpu'] / c:.0f} times less")
        else:
            print(f"traverse {r['disc']}: CPU runs {['%.3g' % c for c in r['cpu_all']]}")


if __name__ == "__main__":
    main()
