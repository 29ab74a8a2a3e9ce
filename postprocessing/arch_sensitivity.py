#!/usr/bin/env python3
"""Is the undamped shallow arch's motion after the snap converged, or sensitive to any
perturbation? (docs/adaptive.md, "Work and precision".)

The scene: inputs/arch/shallow_arch_v0.02.yaml at ds = 0.01 (--ds) with rho_inf = 1 (undamped),
to --end seconds, outputs every 0.0625 s, fixed steps dt = ds / v / k (0.5 s / k at ds = 0.01):
  k = 64, 128, 256, 512                          (refinement in dt)
  k = 256 with the force 2 N times (1 + eps)     (twin: the same numerics, a perturbation of
                                                  eps = 1e-9 in the data)
The separation |r_mid(a) - r_mid(b)| of the midpoint between runs shows which it is: if it
grows at the same exponential rate in the twin (a perturbation far below any discretisation
error) as between dt and dt / 2, the growth belongs to the dynamics (sensitive dependence), and
point-for-point agreement lasts only a time of order log(tolerance / initial difference) / rate;
what converges then is the motion's statistics over a window (mean, spread, extremes, the
dominant frequency of the midpoint), which the script tabulates per run.

Usage: arch_sensitivity.py --traverse BUILD/traverse [--out DIR] [--end 30] [--ds 0.01] [--plot-only]
Writes DIR/arch_sensitivity.csv (pairs), DIR/arch_sensitivity_stats.csv (runs) and
DIR/arch_sensitivity.png; prints both tables.
"""
import argparse
import csv
import os
import resource
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from work_precision import trace  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "inputs", "arch", "shallow_arch_v0.02.yaml")
SPEED = 0.02         # the scene's load speed [m/s]
INTERVAL = 0.0625    # output spacing [s]
FORCE = 2.0          # the scene's force [N]
EPS = 1e-9           # the twin's relative perturbation of the force
RUNS = [("k64", 64, 0.0), ("k128", 128, 0.0), ("k256", 256, 0.0), ("k512", 512, 0.0), ("k256_twin", 256, EPS)]
PAIRS = [("k64", "k512"), ("k128", "k512"), ("k256", "k512"), ("k256", "k256_twin")]


def run(exe, name, k, eps, end, ds, out_dir):
    path = os.path.join(out_dir, f"arch_sensitivity_{name}.h5")
    dt = ds / SPEED / k
    cmd = [exe, "run", SCENE, "-o", path, "--overwrite", "-q",
           "--set", f"mesh.ds={ds:g}", "--set", "scheme.rho_inf=1", "--set", "output.fields=[]",
           "--set", f"time.end={end:g}", "--set", f"time.dt={dt:.17g}",
           "--set", f"output.every={int(round(INTERVAL / dt))}",
           "--set", f"loads.F.force={FORCE * (1.0 + eps):.17g}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        sys.exit(f"arch_sensitivity.py: {' '.join(cmd)} failed ({res.returncode}):\n{res.stdout}{res.stderr}")
    return path, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def snap_time(t, r):
    """The first output time at which the midpoint is below its start by half its height."""
    y = r[:, 1]
    k = np.nonzero(y <= 0.0)[0]
    return float(t[k[0]]) if k.size else float("nan")


def separation(a, b):
    ta, ra = a
    tb, rb = b
    n = min(len(ta), len(tb))
    if np.max(np.abs(ta[:n] - tb[:n])) > 1e-9:
        sys.exit("arch_sensitivity.py: the runs' output times differ")
    return ta[:n], np.linalg.norm(ra[:n] - rb[:n], axis=1)


def first_above(t, d, level):
    k = np.nonzero(d > level)[0]
    return float(t[k[0]]) if k.size else float("nan")


def growth_rate(t, d, t_from, lo=1e-6, hi=1e-2):
    """Mean exponential growth rate [1/s] of the separation after t_from: ln(hi / lo) over the
    time between its first passages above lo and above hi (nan when it starts above lo)."""
    sel = t >= t_from
    t, d = t[sel], d[sel]
    if not d.size or d[0] > lo:
        return float("nan")
    t_lo, t_hi = first_above(t, d, lo), first_above(t, d, hi)
    return float(np.log(hi / lo) / (t_hi - t_lo)) if t_hi > t_lo else float("nan")


def trend(t, r, width=2.0):
    """The midpoint height averaged over a sliding window of `width` seconds (centred; the
    quasi-static drift as the load moves) and the times where the window is complete."""
    n = int(round(width / INTERVAL))
    y = r[:, 1]
    avg = np.convolve(y, np.ones(n) / n, mode="valid")
    return t[n // 2:n // 2 + len(avg)], avg


def stats(t, r, t_from):
    """Statistics of the midpoint height after t_from: its time average, the drift (the 2 s
    sliding average) and the vibration about it (RMS, extremes, dominant frequency above 1 Hz)."""
    tt, avg = trend(t, r)
    sel = tt >= t_from
    y = np.interp(tt[sel], t, r[:, 1])
    fl = y - avg[sel]
    spec = np.abs(np.fft.rfft(fl * np.hanning(len(fl))))
    freq = np.fft.rfftfreq(len(fl), d=INTERVAL)
    band = freq > 1.0
    return {"mean_y": float(y.mean()), "vib_rms": float(np.sqrt(np.mean(fl * fl))), "vib_min": float(fl.min()),
            "vib_max": float(fl.max()), "peak_hz": float(freq[band][int(np.argmax(spec[band]))])}


def trend_difference(a, b, t_from):
    ta, ya = trend(*a)
    tb, yb = trend(*b)
    n = min(len(ta), len(tb))
    sel = ta[:n] >= t_from
    return float(np.max(np.abs(ya[:n][sel] - yb[:n][sel])))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--traverse", help="the traverse executable (not needed with --plot-only)")
    ap.add_argument("--out", default="out/arch_sensitivity")
    ap.add_argument("--end", type=float, default=30.0, help="end time [s] (the load leaves at 50 s)")
    ap.add_argument("--ds", type=float, default=0.01, help="mesh spacing [m]; dt = ds / v / k")
    ap.add_argument("--plot-only", action="store_true", help="use the output files already in --out")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    data, cpu = {}, {}
    for name, k, eps in RUNS:
        path = os.path.join(args.out, f"arch_sensitivity_{name}.h5")
        if not args.plot_only:
            if not args.traverse:
                sys.exit("arch_sensitivity.py: --traverse is required unless --plot-only")
            path, cpu[name] = run(args.traverse, name, k, eps, args.end, args.ds, args.out)
            print(f"{name}: dt = {args.ds / SPEED / k:.6g} s, force x (1 + {eps:g}), CPU {cpu[name]:.2f} s", flush=True)
        data[name] = trace(path, "midpoint")
    t_snap = snap_time(*data["k512"])
    window = t_snap + 1.0
    rows = []
    for a, b in PAIRS:
        t, d = separation(data[a], data[b])
        before = d[t <= t_snap - 0.5]
        rows.append({"pair": f"{a} / {b}", "before_snap_m": float(before.max()) if before.size else float("nan"),
                     "t_1mm": first_above(t, d, 1e-3), "t_1cm": first_above(t, d, 1e-2),
                     "rate_per_s": growth_rate(t, d, t_snap), "max_m": float(d.max()),
                     "trend_m": trend_difference(data[a], data[b], window)})
    srows = []
    for name, _, _ in RUNS:
        s = stats(*data[name], window)
        s["run"] = name
        srows.append(s)
    with open(os.path.join(args.out, "arch_sensitivity.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(args.out, "arch_sensitivity_stats.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["run", "mean_y", "vib_rms", "vib_min", "vib_max", "peak_hz"])
        w.writeheader()
        w.writerows(srows)
    print(f"ds = {args.ds:g} m; snap (midpoint through y = 0, dt = ds / v / 512): t = {t_snap:.4f} s; statistics over t >= {window:.4f} s")
    print("| pair | largest separation to 0.5 s before the snap [m] | first > 1 mm [s] | first > 1 cm [s] |"
          " growth rate 1e-6 -> 1e-2 m after the snap [1/s] | largest [m] | largest drift difference after the window start [m] |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['pair']} | {r['before_snap_m']:.2e} | {r['t_1mm']:.2f} | {r['t_1cm']:.2f} | {r['rate_per_s']:.2f} |"
              f" {r['max_m']:.3f} | {r['trend_m']:.2e} |")
    print("| run | mean y [m] | vibration RMS [m] | vibration min / max [m] | dominant frequency [Hz] |")
    print("|---|---|---|---|---|")
    for s in srows:
        print(f"| {s['run']} | {s['mean_y']:.4f} | {s['vib_rms']:.4f} | {s['vib_min']:.4f} / {s['vib_max']:.4f} |"
              f" {s['peak_hz']:.2f} |")
    plot(data, t_snap, args.ds, os.path.join(args.out, "arch_sensitivity.png"))
    return 0


def plot(data, t_snap, ds, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8, 7.5))
    for a, b in PAIRS:
        t, d = separation(data[a], data[b])
        ax.semilogy(t, np.maximum(d, 1e-16), label=f"{a} vs {b}")
    ax.axvline(t_snap, color="0.5", ls=":", lw=1)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("midpoint separation [m]")
    ax.set_title(f"undamped shallow arch, v = 0.02 m/s, ds = {ds:g}: runs apart (k: dt = ds / v / k; twin: F x (1 + 1e-9))",
                 fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    for name in ("k128", "k512", "k256_twin"):
        t, r = data[name]
        bx.plot(t, r[:, 1], lw=0.8, label=name)
    bx.set_xlim(t_snap - 1.0, t[-1])
    bx.set_xlabel("t [s]")
    bx.set_ylabel("midpoint height y [m]")
    bx.legend(fontsize=8)
    bx.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
