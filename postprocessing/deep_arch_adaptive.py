#!/usr/bin/env python3
"""The deep hinged arch with the time error controlled (docs/adaptive.md): the
lateral midpoint trace x against the load position sigma at v = 0.01 and 0.005 m/s, for
several meshes (mesh.ds, down to the scenes' own) and tolerances (time.adaptive.tolerance),
rho_inf = 1 (the scenes'), outputs every 0.125 s (v = 0.01) and 0.25 s (v = 0.005).

For each run it prints the events of the motion: where the arch flops sideways (|x| first
passes 1 cm), how many excursions about the out-of-plane state follow (maxima of x above 1 cm
before the crossing), the range of x between the first and the last of them, where x comes back
below 1 cm after the last one (the return towards the planar state), where x first passes -1 cm
(the crossing to the other side), its minimum, and the amplitude of the oscillation about the
planar state after sigma = 0.7 m.

--loaded runs every case with initial_state.loaded = true (the arch starts in equilibrium with
the load at s = 0, so its entry is no step; files named *_loaded.h5).

Usage: deep_arch_adaptive.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--loaded]
                             [--runs v:ds:tol ...]
(The twelve default runs take about 25 min of CPU here, most of it the 1e-3 runs.)
Writes DIR/deep_v<v>_ds<ds>_<tol>.h5 per run (an existing complete file is reused),
DIR/deep_arch_adaptive.csv (the events) and DIR/adaptive_deep_arch.png.
"""
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "..", "inputs", "arch")

# (v [m/s], ds [m], tolerance): the scenes' ds is 0.00125 at v = 0.01 and 0.001 at v = 0.005.
DEFAULT_RUNS = [
    (0.01, 0.01, 1e-2), (0.01, 0.01, 1e-3), (0.01, 0.005, 1e-2), (0.01, 0.005, 1e-3), (0.01, 0.00125, 1e-2),
    (0.01, 0.00125, 1e-3), (0.01, 0.001, 1e-2),
    (0.005, 0.01, 1e-2), (0.005, 0.01, 1e-3), (0.005, 0.005, 1e-2), (0.005, 0.001, 1e-2), (0.005, 0.001, 1e-3),
]


def name(v, ds, tol, loaded=False):
    return f"deep_v{v:g}_ds{ds:g}_{tol:g}" + ("_loaded" if loaded else "") + ".h5"


def run(exe, v, ds, tol, out_dir, loaded=False):
    path = os.path.join(out_dir, name(v, ds, tol, loaded))
    if os.path.exists(path):
        try:
            traverse_io.load(path)
            return path
        except Exception:  # incomplete or unreadable: run again
            pass
    interval = 0.125 * 0.01 / v  # outputs every 0.125 s at v = 0.01, 0.25 s at v = 0.005
    scene = os.path.join(INPUTS, f"deep_arch_v{v:g}.yaml")
    cmd = [exe, "run", scene, "-o", path, "--overwrite", "--set", f"mesh.ds={ds:g}",
           "--set", f"time.dt={interval / 2:.17g}", "--set", "output.every=2",
           "--set", f"time.adaptive.tolerance={tol:g}", "--set", "output.fields=[]"]
    if loaded:
        cmd += ["--set", "initial_state.loaded=true"]
    print(" ".join(cmd), flush=True)
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"deep_arch_adaptive.py: run failed ({res.returncode}):\n{res.stdout}{res.stderr}")
    for line in res.stdout.splitlines():
        if line.startswith("adaptive:") or "time stepping" in line:
            print("  " + line.strip()[:160], flush=True)
    return path


def events(path):
    out = traverse_io.load(path)
    sigma = np.asarray(traverse_io.first_load_sigma(out), dtype=float)
    x = np.asarray(out.probes["midpoint"], dtype=float)[:, 0]
    nan = float("nan")
    if not (np.abs(x) > 0.01).any():  # no flop
        return {"flop_sigma": nan, "excursions": 0, "x_min_before": nan, "x_max_before": nan, "return_sigma": nan,
                "cross_sigma": nan, "x_min": float(x.min()),
                "late_amplitude": float(np.abs(x[sigma > 0.7]).max())}, sigma, x
    i = int(np.argmax(np.abs(x) > 0.01))
    j = int(np.argmax(x < -0.01)) if (x < -0.01).any() else len(x)
    seg = x[i:j]
    maxima = [k for k in range(1, len(seg) - 1) if seg[k] > seg[k - 1] and seg[k] >= seg[k + 1] and seg[k] > 0.01]
    back = np.nonzero(seg[maxima[-1]:] < 0.01)[0] if maxima else np.array([], dtype=int)
    # The troughs between the excursions: the lowest x between the first and the last maximum.
    troughs = seg[maxima[0]:maxima[-1] + 1] if len(maxima) > 1 else np.array([np.nan])
    late = np.abs(x[sigma > 0.7])
    return {
        "flop_sigma": float(sigma[i]), "excursions": len(maxima),
        "x_min_before": float(troughs.min()),
        "x_max_before": float(seg.max()) if len(seg) else float("nan"),
        "return_sigma": float(sigma[i + maxima[-1] + back[0]]) if back.size else float("nan"),
        "cross_sigma": float(sigma[j]) if j < len(x) else float("nan"), "x_min": float(x.min()),
        "late_amplitude": float(late.max()) if late.size else float("nan"),
    }, sigma, x


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse")
    ap.add_argument("--out", default="deep_arch_adaptive")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--runs", nargs="*", help="v:ds:tol triples (default: the twelve of docs/adaptive.md)")
    ap.add_argument("--loaded", action="store_true", help="initial_state.loaded = true in every run")
    a = ap.parse_args(argv)
    runs = [tuple(float(p) for p in r.split(":")) for r in a.runs] if a.runs else DEFAULT_RUNS
    if not a.plot_only and not a.traverse:
        sys.exit("deep_arch_adaptive.py: --traverse BUILD/traverse is needed unless --plot-only")
    os.makedirs(a.out, exist_ok=True)
    rows, traces = [], {}
    for v, ds, tol in runs:
        path = (os.path.join(a.out, name(v, ds, tol, a.loaded)) if a.plot_only
                else run(os.path.abspath(a.traverse), v, ds, tol, a.out, a.loaded))
        if not os.path.exists(path):
            print(f"deep_arch_adaptive.py: {path} missing, skipped", file=sys.stderr)
            continue
        e, sigma, x = events(path)
        traces[(v, ds, tol)] = (sigma, x)
        rows.append({"v": v, "ds": ds, "tolerance": tol, **e})
        if np.isnan(e["flop_sigma"]):
            print(f"v = {v:g} m/s, ds = {ds:g} m, tolerance {tol:g}: no flop (|x| <= 1 cm throughout)", flush=True)
            continue
        print(f"v = {v:g} m/s, ds = {ds:g} m, tolerance {tol:g}: flops at sigma = {e['flop_sigma']:.4f} m, "
              f"{e['excursions']} excursions, x in [{e['x_min_before']:.3f}, {e['x_max_before']:.3f}] m between them, "
              f"back below 1 cm at sigma = {e['return_sigma']:.4f} m, "
              f"crosses at sigma = {e['cross_sigma']:.4f} m (min x {e['x_min']:.4f} m), "
              f"|x| <= {e['late_amplitude']:.4f} m after sigma = 0.7 m", flush=True)
    csv_path = os.path.join(a.out, "deep_arch_adaptive" + ("_loaded" if a.loaded else "") + ".csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    speeds = sorted({k[0] for k in traces}, reverse=True)
    fig, axes = plt.subplots(len(speeds), 2, figsize=(12, 3.6 * len(speeds)), squeeze=False,
                             gridspec_kw={"width_ratios": [2, 1]})
    for row, v in zip(axes, speeds):
        for (vv, ds, tol), (sigma, x) in sorted(traces.items(), key=lambda kv: (-kv[0][1], kv[0][2])):
            if vv != v:
                continue
            label = f"ds {ds:g}, tol {tol:g}"
            row[0].plot(sigma, x, lw=0.8, label=label)
            zoom = (sigma > 0.44) & (sigma < 0.6)
            row[1].plot(sigma[zoom], x[zoom], lw=0.9, label=label)
        row[0].set_title(f"deep arch, v = {v:g} m/s (rho_inf = 1, error controlled"
                         + (", start in equilibrium with the load)" if a.loaded else ")"))
        row[1].set_title("flop, excursions, crossing (zoom)")
        for ax in row:
            ax.set_ylabel("midpoint x (lateral) [m]")
            ax.grid(True, alpha=0.3)
        row[0].legend(fontsize=7, loc="lower left")
    for ax in axes[-1]:
        ax.set_xlabel("load position sigma [m]")
    fig.tight_layout()
    png = os.path.join(a.out, "adaptive_deep_arch" + ("_loaded" if a.loaded else "") + ".png")
    fig.savefig(png, dpi=110)
    print(f"wrote {png} and {csv_path}")


if __name__ == "__main__":
    main()
