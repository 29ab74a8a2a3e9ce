#!/usr/bin/env python3
"""Figure of one beam run: tip deflection and deflection under each load against the
load's position x(t) on the beam (the "beam coordinate").

Usage: plot_beam.py RUN.h5 [-o FIGURE.png] [--probe tip]
Exits with status 2 and a message when RUN.h5 is not a complete beam run or has no such probe.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402


def load_names(run):
    """Names of the moving loads of a beam run (from their *_position probes)."""
    return sorted(n[: -len("_position")] for n in run.probes if n.endswith("_position"))


def draw(run, ax, probe="tip", label_prefix=""):
    """Plots probe `probe` (if present) and every load's deflection against the first
    load's position, in mm against m."""
    loads = load_names(run)
    if not loads:
        raise SystemExit("plot_beam: the run has no moving load to plot against")
    x = run.probes[loads[0] + "_position"]
    on = (x >= 0) & (x <= float(run.s[-1]))
    if probe in run.probes:
        ax.plot(x[on], 1e3 * run.probes[probe][on], label=label_prefix + f"{probe} deflection")
    for name in loads:
        xl = run.probes[name + "_position"]
        w = run.probes[name + "_deflection"]
        ok = np.isfinite(w)
        ax.plot(xl[ok], 1e3 * w[ok], "--", label=label_prefix + f"under '{name}'")
    ax.set_xlabel("beam coordinate x(t) [m]")
    ax.set_ylabel("deflection w [mm]")
    ax.grid(True, alpha=0.3)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("-o", "--output", help="PNG file (default: RUN with .png)")
    ap.add_argument("--probe", default="tip", help="probe to draw besides the loads (default: tip)")
    a = ap.parse_args(argv)
    run = traverse_io.load_for_plot(a.run, "beam", "plot_beam")
    traverse_io.require_probe(run, a.probe, "plot_beam")
    fig, ax = plt.subplots(figsize=(7, 4.2))
    draw(run, ax, a.probe)
    ax.set_title(traverse_io.scene_title(run) or os.path.basename(a.run))
    ax.legend()
    fig.tight_layout()
    out = a.output or os.path.splitext(a.run)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"plot_beam: wrote {out}")


if __name__ == "__main__":
    main()
