#!/usr/bin/env python3
"""Hanging-cable figures of the scenes spec. Runs inputs/rod/hanging_cable_F{2,20}_a*.yaml
(alpha in {0.125, 0.25, 0.5, 1.0}) and a resonance sweep over alpha (0.1..2: one `traverse sweep`
per load, its cases spread over the --ranks MPI ranks),
then draws
  hanging_cable_midspan.png   midspan height y(L/2) against sigma, a curve per alpha, a panel per load
  hanging_cable_shapes.png    cable shapes at a few sigma (alpha = 0.5), a panel per load
  hanging_cable_resonance.png against alpha, both loads: (a) the largest midspan deflection
                              while the load is on the cable, divided by its quasi-static value
                              (alpha = 0.1); (b) the amplitude of the free vibration left behind
                              (largest |y(L/2) - y_static| over two periods T1 = 2 pi / omega1
                              after the load has left), divided by the static sag under F

Usage: hanging_cable.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--ranks K]
"""
import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "..", "inputs", "rod")
LOADS = [2, 20]
ALPHAS = [0.125, 0.25, 0.5, 1.0]
SWEEP = [round(0.1 * k, 2) for k in range(1, 21)]
V1 = 7.268366068467048  # omega1 L / pi for the scene rod (see the input files)
T1 = 2.0 / V1  # 2 pi / omega1 with omega1 = pi V1 / L, L = 1 m


def scene(F, a):
    return os.path.join(INPUTS, f"hanging_cable_F{F}_a{a}.yaml")


def out_name(out, F, a, tag="run"):
    return os.path.join(out, f"cable_{tag}_F{F}_a{a}.h5")


def sweep_dir(out, F):
    return os.path.join(out, f"cable_sweep_F{F}")


def run(exe, args, ranks):
    subprocess.run(traverse_io.command(exe, "run", ranks) + args + ["--overwrite", "-q"], check=True)


def run_sweep(exe, out, F, ranks):
    """The resonance sweep of one load in one `traverse sweep` (cases spread over the ranks or
    the worker processes): each speed alpha v1 with its end time (the crossing plus two periods
    of the first mode)."""
    speeds = ",".join(repr(a * V1) for a in SWEEP)
    ends = ",".join(repr(1.0 / (a * V1) + 2 * T1) for a in SWEEP)
    subprocess.run(traverse_io.command(exe, "sweep", ranks) + [
        scene(F, 0.5), "-o", sweep_dir(out, F), "--vary", f"loads.F.speed={speeds}", "--with", f"time.end={ends}",
        "--set", "output.fields=[]", "--overwrite", "-q"], check=True)


def run_all(exe, out, ranks):
    os.makedirs(out, exist_ok=True)
    for F in LOADS:
        for a in ALPHAS:
            run(exe, [scene(F, a), "-o", out_name(out, F, a)], ranks)
        run_sweep(exe, out, F, ranks)


def midspan_y(r):
    return r.probes["midspan"][:, 1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse")
    ap.add_argument("--out", default="out/hanging_cable")
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks of every run and sweep (mpirun)")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args(argv)
    if not a.plot_only:
        if not a.traverse:
            ap.error("--traverse is required unless --plot-only")
        run_all(a.traverse, a.out, a.ranks)

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, F in zip(axes, LOADS):
        for al in ALPHAS:
            r = traverse_io.load(out_name(a.out, F, al))
            ax.plot(traverse_io.first_load_sigma(r), midspan_y(r), label=f"alpha = {al}")
        ax.set_title(f"F = {F} N")
        ax.set_xlabel("load position sigma [m]")
        ax.set_ylabel("midspan height y(L/2) [m]")
        ax.grid(True, alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "hanging_cable_midspan.png"), dpi=120)

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, F in zip(axes, LOADS):
        r = traverse_io.load(out_name(a.out, F, 0.5))
        s = traverse_io.first_load_sigma(r)
        for target in [0.0, 0.25, 0.5, 0.75, 1.0]:
            k = int(np.nanargmin(np.abs(s - target)))
            xyz = r.field("r", k)
            ax.plot(xyz[:, 2], xyz[:, 1], label=f"sigma = {s[k]:.2f} m")
        ax.set_title(f"F = {F} N, alpha = 0.5")
        ax.set_xlabel("z [m]")
        ax.set_ylabel("y [m]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "hanging_cable_shapes.png"), dpi=120)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    for F in LOADS:
        during, after = [], []
        for path in traverse_io.sweep_outputs(sweep_dir(a.out, F)):  # case k: alpha = SWEEP[k]
            r = traverse_io.load(path)
            y, on = midspan_y(r), traverse_io.first_load_sigma(r) <= 1.0
            during.append(np.max(y[0] - y[on]))
            after.append(np.max(np.abs(y[~on] - y[0])))
        during, after = np.array(during), np.array(after)
        ax.plot(SWEEP, during / during[0], "o-", label=f"F = {F} N")
        bx.plot(SWEEP, after / during[0], "o-", label=f"F = {F} N")
        print(f"hanging_cable: F = {F} N: largest deflection ratio {during.max() / during[0]:.3f} at alpha = "
              f"{SWEEP[int(np.argmax(during))]}; largest free-vibration amplitude ratio {after.max() / during[0]:.3f} "
              f"at alpha = {SWEEP[int(np.argmax(after))]}")
    ax.set_title("(a) while the load is on the cable")
    ax.set_ylabel("largest midspan deflection / quasi-static value")
    bx.set_title("(b) free vibration after the load has left")
    bx.set_ylabel("vibration amplitude at midspan / quasi-static deflection")
    for x in (ax, bx):
        x.set_xlabel("speed ratio alpha = v / v1")
        x.grid(True, alpha=0.3)
        x.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "hanging_cable_resonance.png"), dpi=120)
    print(f"hanging_cable: figures in {a.out}")


if __name__ == "__main__":
    main()
