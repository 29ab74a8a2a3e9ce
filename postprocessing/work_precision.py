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
           reference: fixed dt = ds / (256 v) (ds / (64 v) is 1.3e-6 m off, as much as tolerance 1e-5).
  cable-20 the same cable under 20 N (inputs/rod/hanging_cable_F20_a0.5.yaml, ds = 0.01): the
           deep V that travels with the load; reference as for cable.
  arch     shallow arch at v = 0.02 m/s (inputs/arch/shallow_arch_v0.02.yaml at ds = 0.01, the
           scene's rho_inf = 0.8), to t = 16.5 s: the snap position (the load position where the
           right end has turned through half its initial inclination, interpolated between output
           steps every 0.0625 s, or every step when dt is longer); reference: fixed dt / 256,
           output every step.
  arch-slow-undamped  the same at rho_inf = 1 to t = 17 s, outputs every ds / (64 v) (0.16 mm of
           load travel): the snap position; reference: fixed dt = ds / (256 v), output every step.
  arch-undamped  the same at rho_inf = 1 and v = 0.5 m/s (ds = 0.01, the whole crossing): the
           midpoint trace; reference: fixed dt = ds / (256 v).
  arch-undamped-snap  the same scene to t = 1.2 s: the snap position (as in arch, outputs every
           0.0025 s = 1.25 mm of load travel); reference: fixed dt = ds / (256 v), output every step.
  arch-damped-snap  the same at the damped scheme (rho_inf = 0.8).
  arch-2-snap, arch-2-damped-snap  the shallow arch at v = 2 m/s (inputs/arch/shallow_arch_v2.0.yaml,
           ds = 0.01), undamped and at rho_inf = 0.8, to t = 0.5 s (the load leaves): the snap position,
           outputs 1.25 mm of load travel apart; reference: fixed dt = ds / (1024 v).
  deep-arch  the deep arch at v = 0.01 m/s (inputs/arch/deep_arch_v0.01.yaml at ds = 0.01, undamped,
           lateral trigger 1e-6 F) to t = 60 s: the flop onset (the load position where the lateral
           midpoint displacement |x| first passes 1 cm, interpolated between outputs every 0.125 s)
           and the first peak of |x| after it (its value, error_2); reference: fixed dt = ds / (256 v);
           fixed runs from dt = ds / (4 v) (at ds / v Newton fails after the flop).
  robot    the inspection robot on the hanging cable (inputs/rod/coupled_inspection_robot.yaml,
           ds = 0.025, a coupled mass driven along the cable): the time it leaves the cable at s = L;
           fixed dt = 0.025 s (ds over its terminal speed of about 1 m/s) refined; reference dt / 1024.
  bead     the bead sliding down the hanging cable (inputs/rod/coupled_bead_cable.yaml, ds = 0.025, a
           coupled mass launched at 1 m/s, gravity and the cable's motion only): its leaving time, as robot.

Usage: work_precision.py --traverse BUILD/traverse --study STUDY [--out DIR]
       [--loaded] [--plot-only] [--tolerances T ...] [--adaptive-set KEY=VALUE ...]
       work_precision.py --traverse BUILD/traverse --out DIR --summary FIGURE_DIR
Writes DIR/<study>.csv (method, parameter, cpu_s, steps, error, error_2) and DIR/<study>.png.
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
        "reference": ("fixed", 256),
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
STUDIES["arch-slow-undamped"] = {**STUDIES["arch"], "sets": ["mesh.ds=0.01", "time.end=17", "output.fields=[]",
                                                            "scheme.rho_inf=1"],
                                "output_interval": 0.5 / 64, "refine": [4, 16, 64],
                                "tolerances": [1e-2, 1e-3, 1e-4, 1e-5]}


def damped(study, rho_inf=0.8):
    """The study at scheme.rho_inf = rho_inf instead of its own."""
    s = STUDIES[study]
    return {**s, "sets": [kv for kv in s["sets"] if not kv.startswith("scheme.rho_inf=")] + [f"scheme.rho_inf={rho_inf:g}"]}


STUDIES["arch-damped-snap"] = damped("arch-undamped-snap")
STUDIES["arch-2-snap"] = {
    "scene": os.path.join(INPUTS, "arch", "shallow_arch_v2.0.yaml"),
    "sets": ["scheme.rho_inf=1", "output.fields=[]", "time.end=0.5"],
    "dt": 0.005,
    "metric": "snap",
    "output_interval": 0.000625,
    "refine": [1, 4, 16, 64],
    "tolerances": [1e-2, 1e-3, 1e-4, 1e-5],
    "reference": ("fixed", 1024),
}
STUDIES["arch-2-damped-snap"] = damped("arch-2-snap")
STUDIES["deep-arch"] = {
    "scene": os.path.join(INPUTS, "arch", "deep_arch_v0.01.yaml"),
    "sets": ["mesh.ds=0.01", "time.end=60", "output.fields=[]"],
    "dt": 1.0,
    "metric": "flop",
    "output_interval": 0.125,
    "refine": [4, 16, 64],
    "tolerances": [1e-2, 1e-3, 1e-4, 1e-5],
    "reference": ("fixed", 256),
}
STUDIES["robot"] = {
    "scene": os.path.join(INPUTS, "rod", "coupled_inspection_robot.yaml"),
    "sets": ["output.fields=[]"],
    "dt": 0.025,
    "metric": "leave",
    "refine": [1, 4, 16, 64],
    "tolerances": [1e-2, 1e-3, 1e-4, 1e-5],
    "reference": ("fixed", 1024),
}
# The bead: the robot's study on the bead's scene.
STUDIES["bead"] = {**STUDIES["robot"], "scene": os.path.join(INPUTS, "rod", "coupled_bead_cable.yaml")}


LOADED = []  # --loaded: ["initial_state.loaded=true"] (the arch starts in equilibrium with the load)
ADAPTIVE_SETS = []  # --adaptive-set KEY=VALUE: more settings of the adaptive runs (e.g. time.adaptive.on=[u])


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
        for kv in ADAPTIVE_SETS:
            cmd += ["--set", kv]
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


class NoEvent(RuntimeError):
    """The measured event did not happen in a run (or in the reference read at its output times)."""


def at_times(out, times):
    """Indices of the output steps of `out` at `times` (all of them when times is None)."""
    t = np.asarray(out.time, dtype=float)
    if times is None:
        return np.arange(len(t))
    k = np.clip(np.searchsorted(t, np.asarray(times) - 1e-9), 0, len(t) - 1)
    if np.abs(t[k] - times).max() > 1e-9:
        sys.exit(f"work_precision.py: {out.path}: the reference has no output at some of the run's output times")
    return k


def snap_position(out, times=None):
    """The load position sigma [m] where the right end of the shallow arch has turned through
    half its initial inclination (the middle of the snap), interpolated between output steps
    (those at `times` only, when given); no second value."""
    import arches
    theta, alpha0 = arches.right_end_rotation(out)
    sel = at_times(out, times)
    theta, sig = theta[sel], traverse_io.first_load_sigma(out)[sel]
    k = np.nonzero(theta >= 0.5 * alpha0)[0]
    if not k.size:
        raise NoEvent(f"work_precision.py: {out.path}: the arch did not snap")
    k = int(k[0])
    f = (0.5 * alpha0 - theta[k - 1]) / (theta[k] - theta[k - 1])
    return float(sig[k - 1] + f * (sig[k] - sig[k - 1])), None


def flop(out, times=None):
    """The deep arch: the load position [m] where the lateral midpoint displacement |x| first
    passes 1 cm (interpolated between outputs), and the first peak of |x| after it [m] (outputs
    at `times` only, when given)."""
    sel = at_times(out, times)
    x = np.abs(np.asarray(out.probes["midpoint"], dtype=float)[sel, 0])
    sig = traverse_io.first_load_sigma(out)[sel]
    k = np.nonzero(x > 0.01)[0]
    if not k.size:
        raise NoEvent(f"work_precision.py: {out.path}: the arch did not flop (|x| <= 1 cm)")
    k = int(k[0])
    f = (0.01 - x[k - 1]) / (x[k] - x[k - 1])
    falls = np.nonzero(np.diff(x[k:]) < 0.0)[0]
    if not falls.size:
        raise NoEvent(f"work_precision.py: {out.path}: |x| has no peak after the flop before time.end")
    return float(sig[k - 1] + f * (sig[k] - sig[k - 1])), float(x[k + int(falls[0])])


def leaving_time(out, times=None):
    """The coupled mass: the time [s] of its first event (leaving the rod), located inside its
    step (independent of the outputs); no second value."""
    if not out.events:
        raise NoEvent(f"work_precision.py: {out.path}: no event (the mass did not leave the rod)")
    return out.events[0]["time"], None


METRICS = {  # metric: (function of a loaded output [, output times] -> (value, second value or None), what it is)
    "snap": (snap_position, "snap position sigma [m]"),
    "flop": (flop, "flop onset sigma [m]"),
    "leave": (leaving_time, "leaving time [s]"),
}


def study_rows(exe, study, out_dir):
    s = STUDIES[study]
    kind, p = s["reference"]
    ref_path, _, _ = run(exe, study, kind, p, out_dir)
    metric = s.get("metric")
    if metric:
        ref_out = traverse_io.load(ref_path)
        ref, ref_2 = METRICS[metric][0](ref_out)
        print(f"{study}: reference {METRICS[metric][1]} = {ref:.9g}" +
              (f", second value {ref_2:.9g}" if ref_2 is not None else ""), flush=True)
    else:
        t_ref, x_ref = trace(ref_path, s["probe"])
    rows = []
    cases = [("fixed", k) for k in s["refine"]] + [("adaptive", tol) for tol in s["tolerances"]]
    for method, param in cases:
        path, cpu, steps = run(exe, study, method, param, out_dir)
        err_2 = ""
        if metric:
            # The reference read at this run's output times: the measure's interpolation between
            # outputs is then common to both, and the error is the time stepping's.
            # A reference that passes the event between this run's outputs (a short first flip)
            # is read in full.
            out = traverse_io.load(path)
            value, value_2 = METRICS[metric][0](out)
            try:
                ref, ref_2 = METRICS[metric][0](ref_out, out.time)
            except NoEvent:
                ref, ref_2 = METRICS[metric][0](ref_out)
            err = abs(value - ref)
            if value_2 is not None:
                err_2 = abs(value_2 - ref_2)
        else:
            t, x = trace(path, s["probe"])
            if len(t) != len(t_ref) or np.abs(t - t_ref).max() > 1e-9:
                sys.exit(f"work_precision.py: {path}: output times differ from the reference's")
            err = float(np.linalg.norm(x - x_ref, axis=1).max())
        rows.append({"method": method, "parameter": param, "cpu_s": cpu, "steps": steps, "error": err,
                     "error_2": err_2})
        print(f"{study}: {method:8s} {param:<8g} cpu {cpu:7.2f} s  steps {steps:7d}  error {err:.3e}" +
              (f"  error_2 {err_2:.3e}" if err_2 != "" else ""), flush=True)
    return rows


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["method", "parameter", "cpu_s", "steps", "error", "error_2"])
        w.writeheader()
        for r in rows:
            w.writerow(r)


def read_csv(path):
    with open(path) as f:
        return [{"method": r["method"], "parameter": float(r["parameter"]), "cpu_s": float(r["cpu_s"]),
                 "steps": int(r["steps"]), "error": float(r["error"]),
                 "error_2": float(r["error_2"]) if r.get("error_2") else ""} for r in csv.DictReader(f)]


def draw_work_precision(ax, rows, fontsize=7, ms=None):
    """Error against CPU, fixed steps (labelled /k) and adaptive ones (labelled by the tolerance)."""
    for method, style, label in [("fixed", "o-", "fixed dt (ds/v, /2, /4, ...)"), ("adaptive", "s-", "adaptive")]:
        rs = [r for r in rows if r["method"] == method]
        ax.loglog([r["cpu_s"] for r in rs], [r["error"] for r in rs], style, ms=ms, label=label)
        for r in rs:
            txt = f"/{int(r['parameter'])}" if method == "fixed" else f"{r['parameter']:.0e}"
            ax.annotate(txt, (r["cpu_s"], r["error"]), textcoords="offset points", xytext=(3, 3), fontsize=fontsize)


def plot(rows, study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    draw_work_precision(ax, rows)
    ax.set_xlabel("CPU time of the whole process [s]")
    metric = STUDIES[study].get("metric")
    ax.set_ylabel(f"|error| of the {METRICS[metric][1]}" if metric
                  else f"max |error| of the {STUDIES[study]['probe']} trace [m]")
    ax.set_title(f"work-precision: {study}" + (" (start loaded)" if LOADED else ""))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=130)


SUMMARY = [  # (study, panel title) in the order of docs/adaptive.md's table
    ("cable", "hanging cable, 2 N: midspan trace"),
    ("cable-20", "hanging cable, 20 N: midspan trace"),
    ("arch", "shallow arch 0.02 m/s, damped: snap"),
    ("arch-slow-undamped", "shallow arch 0.02 m/s, undamped: snap"),
    ("arch-damped-snap", "shallow arch 0.5 m/s, damped: snap"),
    ("arch-undamped-snap", "shallow arch 0.5 m/s, undamped: snap"),
    ("arch-2-damped-snap", "shallow arch 2 m/s, damped: snap"),
    ("arch-2-snap", "shallow arch 2 m/s, undamped: snap"),
    ("deep-arch", "deep arch 0.01 m/s: flop onset"),
    ("bead", "bead on the cable: leaving time"),
    ("robot", "inspection robot: leaving time"),
]


def plot_summary(out_dir, fig_dir):
    """Every study's CSV found in out_dir: the work-precision panels (error against CPU, fixed and
    adaptive) and the tolerance proportionality (the adaptive error against the tolerance, each
    study divided by its error at the loosest tolerance, beside the slope-1 line)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    found = [(st, title) for st, title in SUMMARY if os.path.exists(os.path.join(out_dir, st + ".csv"))]
    if not found:
        sys.exit(f"work_precision.py: no study CSV in {out_dir}")
    cols = min(4, len(found))
    rows_n = (len(found) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(3.4 * cols, 2.9 * rows_n), squeeze=False)
    for ax, (st, title) in zip(axes.flat, found):
        rows = read_csv(os.path.join(out_dir, st + ".csv"))
        draw_work_precision(ax, rows, fontsize=6, ms=4)
        metric = STUDIES[st].get("metric")
        ax.set_title(title, fontsize=8)
        ax.set_ylabel("error [s]" if metric == "leave" else "error [m]", fontsize=7)
        ax.set_xlabel("CPU [s]", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.set_xticks([x for x in (0.2, 0.3, 0.5, 1, 2, 3, 5, 10, 20) if min(r["cpu_s"] for r in rows) / 1.2 <= x
                       <= max(r["cpu_s"] for r in rows) * 1.2])
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(found):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(fig_dir, "adaptive_work_precision.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6, 4.4))
    for st, title in found:
        rs = sorted((r for r in read_csv(os.path.join(out_dir, st + ".csv")) if r["method"] == "adaptive"),
                    key=lambda r: -r["parameter"])
        tol = np.array([r["parameter"] for r in rs])
        err = np.array([r["error"] for r in rs])
        # Normalised at 1e-3: at 1e-2 the output spacing, not the tolerance, limits most runs' steps.
        k = int(np.argmin(np.abs(np.log(tol / 1e-3))))
        ax.loglog(tol, err / err[k] * (tol[k] / 1e-3), "o-", ms=3, label=title)
    t = np.array([1e-2, 1e-5])
    ax.loglog(t, t / 1e-3, "k--", lw=2, label="proportional (slope 1)")
    ax.set_xlabel("tolerance")
    ax.set_ylabel("error / error at tolerance 1e-3")
    ax.set_title("tolerance proportionality of the adaptive runs")
    ax.invert_xaxis()
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="lower left")
    fig.tight_layout()
    path2 = os.path.join(fig_dir, "adaptive_tolerance_proportionality.png")
    fig.savefig(path2, dpi=120)
    print(f"wrote {path} and {path2}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse", required=True)
    ap.add_argument("--study", choices=sorted(STUDIES))
    ap.add_argument("--summary", metavar="FIGURE_DIR",
                    help="draw the summary figures of every study CSV in --out into FIGURE_DIR (no runs)")
    ap.add_argument("--out", default="work_precision")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--loaded", action="store_true",
                    help="arch studies: initial_state.loaded=true (the start in equilibrium with the load at t = 0)")
    ap.add_argument("--adaptive-set", action="append", default=[], metavar="KEY=VALUE",
                    help="a setting of the adaptive runs only (repeatable), e.g. time.adaptive.on=[position]")
    ap.add_argument("--tolerances", type=float, nargs="+", help="the adaptive runs' tolerances (default: the study's)")
    a = ap.parse_args(argv)
    if a.summary:
        plot_summary(a.out, a.summary)
        return
    if not a.study:
        ap.error("--study (or --summary) is required")
    ADAPTIVE_SETS.extend(a.adaptive_set)
    if a.tolerances:
        STUDIES[a.study]["tolerances"] = a.tolerances
    if a.loaded:
        if "arch" not in a.study:
            sys.exit("work_precision.py: --loaded applies to the arch studies")
        LOADED.append("initial_state.loaded=true")
    os.makedirs(a.out, exist_ok=True)
    csv_path = os.path.join(a.out, f"{a.study}.csv")
    try:
        rows = read_csv(csv_path) if a.plot_only else study_rows(os.path.abspath(a.traverse), a.study, a.out)
    except NoEvent as e:
        sys.exit(str(e))
    if not a.plot_only:
        write_csv(rows, csv_path)
    plot(rows, a.study, os.path.join(a.out, f"{a.study}.png"))
    print(f"wrote {csv_path} and {os.path.join(a.out, a.study + '.png')}")


if __name__ == "__main__":
    main()
