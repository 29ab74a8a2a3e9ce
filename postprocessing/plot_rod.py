#!/usr/bin/env python3
"""Figure of one rod run: the vertical position of a probe (default: midspan) against the
load position sigma, and the shapes y(z) of the centreline at a few sigma (needs the field r),
each with the load marked where it is on that shape. A shape whose largest vertical
displacement from the straight rod is below a tenth of its length is drawn with that
displacement exaggerated (traverse_io.exaggeration), and the axis says by how much. The title
gives the values the run used (its stored scene, after any --set).

Usage: plot_rod.py RUN.h5 [-o FIGURE.png] [--probe midspan]
Exits with status 2 and a message when RUN.h5 is not a complete rod run or has no such probe.
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


def shapes_at(run, sigmas):
    """[(sigma, r (nodes x 3))] for the output steps nearest the given load positions."""
    sig = traverse_io.first_load_sigma(run)
    out = []
    for target in sigmas:
        k = int(np.nanargmin(np.abs(sig - target)))
        out.append((sig[k], run.field("r", k)))
    return out


def point_at(s, r, sigma):
    """The centreline r (nodes x 3) at arclength sigma (linear between nodes), or None off the rod."""
    if not np.isfinite(sigma) or sigma < s[0] or sigma > s[-1]:
        return None
    return np.array([np.interp(sigma, s, r[:, c]) for c in range(3)])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("-o", "--output")
    ap.add_argument("--probe", default="midspan")
    a = ap.parse_args(argv)
    run = traverse_io.load_for_plot(a.run, "rod", "plot_rod")
    traverse_io.require_probe(run, a.probe, "plot_rod")
    has_r = "r" in run.field_names
    fig, axes = plt.subplots(1, 2 if has_r else 1, figsize=(12 if has_r else 7, 4.2), squeeze=False)
    ax = axes[0, 0]
    sig = traverse_io.first_load_sigma(run)
    ax.plot(sig, run.probes[a.probe][:, 1], label=f"{a.probe} y")
    ax.set_xlabel("load position sigma [m]")
    ax.set_ylabel("vertical position y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    if has_r:
        ax2 = axes[0, 1]
        shapes = shapes_at(run, np.linspace(0.0, float(run.s[-1]), 5))
        # The rod starts straight along z: y is its vertical displacement.
        k = traverse_io.exaggeration(np.array([r[:, 1] for _, r in shapes]), float(run.s[-1] - run.s[0]))
        for i, (s, r) in enumerate(shapes):
            line, = ax2.plot(r[:, 2], k * r[:, 1], label=f"sigma = {s:.2f} m")
            p = point_at(run.s, r, s)
            if p is not None:  # the load on this shape
                ax2.plot(p[2], k * p[1], "v", color=line.get_color(), markersize=8,
                         label="load position" if i == 0 else None)
        ax2.set_xlabel("z [m]")
        ax2.set_ylabel("y [m]" if k == 1.0 else f"y, exaggerated x {k:g} [m]")
        if k != 1.0:
            ax2.set_title(f"shapes, vertical displacement exaggerated {k:g} times", fontsize=10)
        ax2.set_aspect("equal", adjustable="datalim")
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8)
    fig.suptitle(traverse_io.wrapped(traverse_io.run_title(run), 120))
    fig.tight_layout()
    out = a.output or os.path.splitext(a.run)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"plot_rod: wrote {out}")


if __name__ == "__main__":
    main()
