#!/usr/bin/env python3
"""Cantilever launch-barrel sweep of the scenes spec: runs inputs/beam/cantilever.yaml for
mass fractions p in {5, 10, 20, 40} % and speeds v in {10, 50, 100, 200} m/s (in
one `traverse sweep`, its cases spread over --ranks MPI ranks; no file copies), then draws
  cantilever_tip_by_speed.png  (a) one panel per v, a curve per mass fraction p
  cantilever_tip_by_mass.png   (b) one panel per mass fraction p, a curve per v
  cantilever_mass.png          deflection under the mass, one panel per v
all against the beam coordinate x(t) = v t; the panels of a figure share one y scale. The mass
fraction p is the moving mass over the beam's mass, M / (rho A L).

Usage: cantilever_sweep.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--modes N] [--ranks K]
"""
import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

FRACTIONS = [0.05, 0.10, 0.20, 0.40]
SPEEDS = [10.0, 50.0, 100.0, 200.0]
HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "inputs", "beam", "cantilever.yaml")


def sweep_dir(out):
    return os.path.join(out, "sweep")


def run_name(out, p, v):
    """The case file of mass fraction p and speed v, from the sweep's index."""
    for row in traverse_io.sweep_index(sweep_dir(out)):
        if float(row["loads.mass.mass_fraction"]) == p and float(row["loads.mass.speed"]) == v:
            if row["status"] != "complete":
                raise traverse_io.IncompleteOutputError(f"case p = {p}, v = {v}: {row['status']} {row['message']}")
            return os.path.join(sweep_dir(out), row["output"])
    raise KeyError(f"{sweep_dir(out)}: no case p = {p}, v = {v} in the sweep's index")


def run_all(exe, out, modes, ranks):
    """The 4 x 4 cases in one `traverse sweep` (spread over `ranks` MPI ranks)."""
    os.makedirs(out, exist_ok=True)
    cmd = traverse_io.command(exe, "sweep", ranks) + [
        SCENE, "-o", sweep_dir(out), "--overwrite", "-q",
        "--vary", "loads.mass.mass_fraction=" + ",".join(repr(p) for p in FRACTIONS),
        "--vary", "loads.mass.speed=" + ",".join(repr(v) for v in SPEEDS),
        "--set", f"beam.modes={modes}", "--summary", "tip:min"]
    subprocess.run(cmd, check=True)


def curve(run):
    x = run.probes["mass_position"]
    on = (x >= 0) & (x <= float(run.s[-1]))
    return x[on], 1e3 * run.probes["tip"][on], 1e3 * run.probes["mass_deflection"][on]


def panels(out, outer, inner, outer_label, inner_label, legend_title, key, fname, which):
    """A 2 x 2 figure, one panel per value of `outer`, a curve per value of `inner`; the
    panels share one y scale (they are compared with each other). Returns the figure (its
    label: fname) after saving it as out/fname."""
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True, sharey=True)
    fig.set_label(fname)
    for ax, o in zip(axes.flat, outer):
        for i in inner:
            p, v = key(o, i)
            x, tip, mass = curve(traverse_io.load(run_name(out, p, v)))
            ax.plot(x, tip if which == "tip" else mass, label=inner_label(i))
        ax.set_title(outer_label(o))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, title=legend_title, title_fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel(("tip deflection" if which == "tip" else "deflection under the mass") + " [mm]")
    for ax in axes[-1]:
        ax.set_xlabel("beam coordinate x(t) = v t [m]")
    fig.tight_layout()
    path = os.path.join(out, fname)
    fig.savefig(path, dpi=120)
    print(f"cantilever_sweep: wrote {path}")
    return fig


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse", help="path of the traverse executable")
    ap.add_argument("--out", default="out/cantilever")
    ap.add_argument("--modes", type=int, default=3)
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks to spread the cases over")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--keep-open", action="store_true", help=argparse.SUPPRESS)  # tests read the figures back
    a = ap.parse_args(argv)
    if not a.plot_only:
        if not a.traverse:
            ap.error("--traverse is required unless --plot-only")
        run_all(a.traverse, a.out, a.modes, a.ranks)
    # p: the moving mass as a fraction of the beam's mass (loads.mass.mass_fraction).
    pct = lambda p: f"p = {round(100 * p)} %"  # noqa: E731
    spd = lambda v: f"v = {v:g} m/s"  # noqa: E731
    fraction = "mass fraction p = M / (rho A L)"
    figures = [
        panels(a.out, SPEEDS, FRACTIONS, spd, pct, fraction, lambda v, p: (p, v), "cantilever_tip_by_speed.png", "tip"),
        panels(a.out, FRACTIONS, SPEEDS, lambda p: f"mass fraction {pct(p)}", spd, "speed", lambda p, v: (p, v),
               "cantilever_tip_by_mass.png", "tip"),
        panels(a.out, SPEEDS, FRACTIONS, spd, pct, fraction, lambda v, p: (p, v), "cantilever_mass.png", "mass"),
    ]
    if not a.keep_open:
        for fig in figures:
            plt.close(fig)


if __name__ == "__main__":
    main()
